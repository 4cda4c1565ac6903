#include "app/record/trace_record.hpp"

#include "app/record/json_line.hpp"
#include "wire/describe.hpp"
#include "wire/framer.hpp"
#include "wire/hex.hpp"
#include "wire/instruction_decoder.hpp"

namespace dxlemu::app {
namespace {

constexpr double kNsPerSecond = 1e9;
constexpr double kNsPerUs = 1e3;

JsonLine record(const std::string& port, sim::SimTime at, const char* direction,
                wire::Protocol protocol) {
  JsonLine out;
  out.real("t", static_cast<double>(sim::ns_since_start(at)) / kNsPerSecond)
      .text("port", port)
      .text("dir", direction);
  if (const int number = wire::protocol_number(protocol); number != 0) {
    out.integer("protocol", number);
  } else {
    out.text("protocol", wire::protocol_name(protocol));
  }
  return out;
}

const char* failure_name(wire::FramingErrorKind kind) {
  switch (kind) {
    case wire::FramingErrorKind::Garbage:
      return "garbage";
    case wire::FramingErrorKind::BadCheck:
      return "bad_check";
    case wire::FramingErrorKind::ImpossibleLength:
      return "impossible_length";
    case wire::FramingErrorKind::Truncated:
      return "truncated";
  }
  return "unknown";
}

// The describe() text of one status frame (or a Fast reply, whose block lengths only the
// request knows), or why it does not decode.
std::string status_text(const wire::Frame& frame) {
  if (wire::is_fast_reply(frame.protocol, frame.id, frame.instruction)) {
    return "id=254 fast_reply";
  }
  const auto status = wire::decode_status(frame);
  if (const auto* error = std::get_if<wire::DecodeError>(&status)) {
    return "undecodable status: " + error->reason;
  }
  return wire::describe(std::get<wire::StatusPacket>(status));
}

}  // namespace

std::string heard_record(const std::string& port, const wire::FramerEvent& event) {
  if (const auto* failure = std::get_if<wire::FramingError>(&event)) {
    JsonLine out = record(port, failure->at, "in", failure->protocol);
    out.text("problem", failure_name(failure->kind))
        .integer("bytes", static_cast<std::int64_t>(failure->bytes));
    if (failure->id) {
      out.integer("id", *failure->id);
    }
    return out.finish();
  }
  const auto& frame = std::get<wire::Frame>(event);
  JsonLine out = record(port, frame.last_byte_at, "in", frame.protocol);
  out.integer("id", frame.id).text("hex", wire::to_hex(frame.raw));
  const auto decoded = wire::decode_instruction(frame);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    out.text("problem", error->reason);
  } else {
    out.text("packet", wire::describe(std::get<wire::InstructionPacket>(decoded)));
  }
  return out.finish();
}

std::string sent_record(const std::string& port, std::span<const std::uint8_t> bytes,
                        sim::SimTime at, wire::Protocol protocol,
                        std::optional<sim::SimDuration> late) {
  JsonLine out = record(port, at, "out", protocol);
  out.text("hex", wire::to_hex(bytes));
  // One delivery holds one packet, except where replies collided or a Fast reply was cut short:
  // say what the client would make of the bytes.
  wire::Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, at, events);
  framer.end_of_write(events);  // a frame that ends at a silence: the delivery is all of it
  std::string text;
  for (const auto& event : events) {
    if (const auto* frame = std::get_if<wire::Frame>(&event)) {
      text += (text.empty() ? "" : "; ") + status_text(*frame);
    }
  }
  if (text.empty()) {
    out.text("problem", "not a complete packet (colliding or cut-short replies)");
  } else {
    out.text("packet", text);
  }
  if (late) {
    out.real("late_us", static_cast<double>(late->count()) / kNsPerUs);
  }
  return out.finish();
}

}  // namespace dxlemu::app
