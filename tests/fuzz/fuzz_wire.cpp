// libFuzzer target for the wire codec of one protocol (DXLEMU_FUZZ_PROTOCOL = V1, V2 or Feetech, a
// wire::Protocol enumerator; CMake builds fuzz_wire_v1, fuzz_wire_v2 and fuzz_wire_feetech from
// this file). The input is a byte stream as a client would put
// it on the bus, cut into chunks that arrive at fuzzer-chosen times (fuzz_input.hpp). Every frame
// the Framer yields goes through every decoder, and what decodes must survive a round trip
// through the encoders. Broken invariants abort, so libFuzzer saves the input.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "fuzz_input.hpp"
#include "fuzz_require.hpp"
#include "repair_checks.hpp"
#include "sim/sim_time.hpp"
#include "wire/crc16.hpp"
#include "wire/describe.hpp"
#include "wire/frame.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"
#include "wire/protocol.hpp"

#if !defined(DXLEMU_FUZZ_PROTOCOL)
#error "compile with -DDXLEMU_FUZZ_PROTOCOL=V1, V2 or Feetech"
#endif

namespace dxlemu::fuzz {
namespace {

using sim::SimDuration;
using sim::SimTime;
using wire::Frame;
using wire::FramerEvent;
using wire::FramingError;
using wire::FramingErrorKind;
using wire::Protocol;

constexpr Protocol kProtocol = Protocol::DXLEMU_FUZZ_PROTOCOL;

// Start the clock away from zero so that a time stamp of SimTime{} in an event stands out as wrong.
constexpr SimTime kStart = sim::sim_time_from_ns(1'000'000'000);
// "Far in the future" for the final expire(): beyond any timeout, however many gaps came before.
constexpr SimDuration kFarFuture = std::chrono::hours(24);

// Fast Sync/Bulk Read reply layout (protocol2.md "Fast Sync Read (0x8A)"): blocks start after
// FF FF FD 00 FE LEN_L LEN_H 0x55 and are [error, ID, data, CRC_L, CRC_H].
constexpr std::size_t kFastReplyBlocksAt = 8;
constexpr std::size_t kFastReplyBlockHead = 2;  // error, ID
constexpr std::size_t kCrcBytes = 2;

const wire::FrameFormat& format() {
  static const wire::FrameFormat f = wire::FrameFormat::for_protocol(kProtocol);
  return f;
}

std::size_t prefix_bytes() {
  return format().header.size() + 1 + format().length_field_bytes;  // header, ID, LENGTH
}

// The frames that answer Fast Sync/Bulk Read. The framer leaves them unstuffed on purpose
// (protocol2.md: such replies are never stuffed), so a StatusPacket or UnknownInstruction decoded
// from one cannot survive encode_status/encode_instruction, which stuff: their round trip is
// checked through decode_fast_reply/encode_fast_reply instead.
bool is_fast_reply_frame(const Frame& frame) {
  return frame.protocol == Protocol::V2 && frame.id == wire::kBroadcastId &&
         frame.instruction == wire::to_byte(wire::InstructionCode::Status);
}

// Frames `bytes` with a fresh framer; they must be exactly one packet and nothing else.
Frame reframe(const std::vector<std::uint8_t>& bytes) {
  wire::Framer framer(kProtocol);
  std::vector<FramerEvent> events;
  framer.feed(bytes, kStart, events);
  framer.expire(kStart + kFarFuture, events);
  FUZZ_REQUIRE(events.size() == 1);
  const Frame* frame = std::get_if<Frame>(&events.front());
  FUZZ_REQUIRE(frame != nullptr);
  FUZZ_REQUIRE(frame->raw == bytes);
  return *frame;
}

void check_decode_error(const wire::DecodeError& error, const Frame& frame) {
  FUZZ_REQUIRE(error.id == frame.id);
  FUZZ_REQUIRE(error.instruction == frame.instruction);
  FUZZ_REQUIRE(!error.reason.empty());
}

void check_instruction(const Frame& frame) {
  const auto decoded = wire::decode_instruction(frame);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    check_decode_error(*error, frame);
    return;
  }
  const auto& packet = std::get<wire::InstructionPacket>(decoded);
  FUZZ_REQUIRE(packet.protocol == kProtocol);
  FUZZ_REQUIRE(packet.id == frame.id);
  FUZZ_REQUIRE(wire::instruction_code(packet.instruction) == frame.instruction);
  FUZZ_REQUIRE(!wire::describe(packet).empty());
  if (is_fast_reply_frame(frame)) {
    return;
  }
  // Not caught on purpose: a decoded packet the encoder refuses is a codec bug.
  const std::vector<std::uint8_t> bytes = wire::encode_instruction(packet);
  if (wire::has_v1_layout(kProtocol)) {
    // 1.0 and FEETECH have no stuffing and one layout per instruction: the packet comes back byte
    // for byte.
    FUZZ_REQUIRE(bytes == frame.raw);
  }
  // A sender that left "FF FF FD" in its parameters unstuffed sent a shorter packet than the
  // encoder makes: near the 2.0 size limit the stuffed form may be longer than any framer accepts
  // (docs/wire.md), so it cannot be framed again (found by a long run of fuzz_wire_v2).
  const wire::FrameFormat format = wire::FrameFormat::for_protocol(kProtocol);
  const std::size_t overhead = format.header.size() + 1 + format.length_field_bytes;
  if (bytes.size() > frame.raw.size() && bytes.size() - overhead > format.max_length) {
    return;
  }
  const auto again = wire::decode_instruction(reframe(bytes));
  const auto* packet_again = std::get_if<wire::InstructionPacket>(&again);
  FUZZ_REQUIRE(packet_again != nullptr);
  FUZZ_REQUIRE(*packet_again == packet);
}

void check_status(const Frame& frame) {
  const auto decoded = wire::decode_status(frame);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    // In 1.0 and FEETECH every packet reads as a status.
    FUZZ_REQUIRE(!wire::has_v1_layout(kProtocol));
    check_decode_error(*error, frame);
    return;
  }
  const auto& status = std::get<wire::StatusPacket>(decoded);
  FUZZ_REQUIRE(status.protocol == kProtocol);
  FUZZ_REQUIRE(status.id == frame.id);
  FUZZ_REQUIRE(!wire::describe(status).empty());
  if (is_fast_reply_frame(frame)) {
    return;
  }
  const std::vector<std::uint8_t> bytes = wire::encode_status(status);
  if (wire::has_v1_layout(kProtocol)) {
    FUZZ_REQUIRE(bytes == frame.raw);
  }
  const auto again = wire::decode_status(reframe(bytes));
  const auto* status_again = std::get_if<wire::StatusPacket>(&again);
  FUZZ_REQUIRE(status_again != nullptr);
  FUZZ_REQUIRE(*status_again == status);
}

// Block data lengths read off the packet itself: each block ends where the running CRC of the
// packet so far follows it. The last block always ends at the packet's own CRC, so for any
// verified fast-reply frame this finds a split that decodes (or stops early on a chance match
// that leaves too few bytes for another block).
std::vector<std::uint16_t> lengths_from_crcs(const Frame& frame) {
  const std::span<const std::uint8_t> raw(frame.raw);
  std::vector<std::uint16_t> lengths;
  std::size_t at = kFastReplyBlocksAt;
  while (at + kFastReplyBlockHead + kCrcBytes <= raw.size()) {
    std::size_t end = at + kFastReplyBlockHead;
    std::uint16_t crc = wire::crc16(raw.first(end));
    while (end + kCrcBytes <= raw.size() &&
           !(raw[end] == (crc & 0xFFU) && raw[end + 1] == (crc >> 8))) {
      crc = wire::crc16_update(crc, raw.subspan(end, 1));
      ++end;
    }
    if (end + kCrcBytes > raw.size()) {
      break;
    }
    lengths.push_back(static_cast<std::uint16_t>(end - at - kFastReplyBlockHead));
    at = end + kCrcBytes;
  }
  return lengths;
}

void check_fast_reply(const Frame& frame, std::span<const std::uint16_t> lengths) {
  const auto decoded = wire::decode_fast_reply(frame, lengths);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    check_decode_error(*error, frame);
    return;
  }
  FUZZ_REQUIRE(is_fast_reply_frame(frame));
  const auto& reply = std::get<wire::FastReply>(decoded);
  FUZZ_REQUIRE(reply.blocks.size() == lengths.size());
  FUZZ_REQUIRE(!wire::describe(reply).empty());
  // A fast reply is never stuffed and every byte of it is a field or a verified CRC, so it
  // re-encodes to exactly the bytes it came from.
  FUZZ_REQUIRE(wire::encode_fast_reply(reply) == frame.raw);
}

void check_fast_replies(const Frame& frame) {
  if (frame.id != wire::kBroadcastId ||
      frame.instruction != wire::to_byte(wire::InstructionCode::Status)) {
    return;
  }
  std::vector<std::uint16_t> lengths = lengths_from_crcs(frame);
  const std::size_t blocks_bytes =
      frame.raw.size() > kFastReplyBlocksAt ? frame.raw.size() - kFastReplyBlocksAt : 0;
  std::size_t covered = 0;
  for (const std::uint16_t n : lengths) {
    covered += kFastReplyBlockHead + n + kCrcBytes;
  }
  const auto decoded = wire::decode_fast_reply(frame, lengths);
  // When the lengths cover the whole packet, the reply must decode (the CRCs were just found).
  FUZZ_REQUIRE(std::holds_alternative<wire::FastReply>(decoded) ==
               (kProtocol == Protocol::V2 && !lengths.empty() && covered == blocks_bytes));
  check_fast_reply(frame, lengths);
  // A split that adds up but puts the first block boundary one byte early exercises the
  // per-block CRC check; no lengths at all exercises the empty request.
  if (lengths.size() >= 2 && lengths[0] > 0) {
    --lengths[0];
    ++lengths[1];
    check_fast_reply(frame, lengths);
  }
  check_fast_reply(frame, {});
}

void check_frame(const Frame& frame, SimTime now) {
  FUZZ_REQUIRE(frame.protocol == kProtocol);
  FUZZ_REQUIRE(frame.raw.size() >= prefix_bytes() + format().min_length);
  FUZZ_REQUIRE(std::equal(format().header.begin(), format().header.end(), frame.raw.begin()));
  FUZZ_REQUIRE(frame.raw[format().header.size()] == frame.id);
  FUZZ_REQUIRE(kStart <= frame.first_byte_at);
  FUZZ_REQUIRE(frame.first_byte_at <= frame.last_byte_at);
  FUZZ_REQUIRE(frame.last_byte_at <= now);
  check_instruction(frame);
  check_status(frame);
  check_fast_replies(frame);
}

// Bytes the events of one input account for: whole frames plus skipped garbage. Each byte fed
// is passed over once, so these and the bytes still buffered can never add up to more than the
// bytes fed (bytes of rejected packets are rescanned, hence "never more", not "equal").
struct Accounting {
  std::size_t fed = 0;
  std::size_t accounted = 0;
};

void check_events(const std::vector<FramerEvent>& events, const wire::Framer& framer, SimTime now,
                  Accounting& accounting) {
  for (const FramerEvent& event : events) {
    if (const auto* frame = std::get_if<Frame>(&event)) {
      check_frame(*frame, now);
      accounting.accounted += frame->raw.size();
      continue;
    }
    const auto& error = std::get<FramingError>(event);
    FUZZ_REQUIRE(error.protocol == kProtocol);
    FUZZ_REQUIRE(error.bytes > 0);
    FUZZ_REQUIRE(kStart <= error.at && error.at <= now);
    if (error.kind == FramingErrorKind::Garbage) {
      accounting.accounted += error.bytes;
    }
  }
  FUZZ_REQUIRE(accounting.accounted + framer.buffered() <= accounting.fed);
  FUZZ_REQUIRE(framer.deadline().has_value() == (framer.buffered() > 0));
}

SimTime after_gap(std::uint8_t gap, SimTime now, const wire::Framer& framer) {
  if (gap == kGapToDeadline) {
    return framer.deadline().value_or(now);
  }
  return now + format().inter_byte_timeout * gap / kGapUnitsPerTimeout;
}

}  // namespace
}  // namespace dxlemu::fuzz

/// libFuzzer's entry point: one input, one fresh framer.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu::fuzz;
  const FuzzInput input = parse_fuzz_input(std::span(data, size));
  std::vector<std::uint8_t> stream(input.stream.begin(), input.stream.end());
  if (input.repair_checks) {
    constexpr std::array kProtocols = {kProtocol};
    repair_checks(stream, kProtocols);
  }

  dxlemu::wire::Framer framer(kProtocol);
  std::vector<FramerEvent> events;
  Accounting accounting;
  SimTime now = kStart;
  std::size_t offset = 0;
  auto feed = [&](std::size_t length) {
    const std::span<const std::uint8_t> chunk(stream.data() + offset, length);
    offset += length;
    accounting.fed += length;
    events.clear();
    framer.feed(chunk, now, events);
    check_events(events, framer, now, accounting);
  };
  for (const Chunk& chunk : input.chunks) {
    now = after_gap(chunk.gap, now, framer);
    feed(std::min<std::size_t>(chunk.length, stream.size() - offset));
  }
  feed(stream.size() - offset);

  events.clear();
  now += kFarFuture;
  framer.expire(now, events);
  check_events(events, framer, now, accounting);
  FUZZ_REQUIRE(framer.buffered() == 0);
  return 0;
}

/// Makes UndefinedBehaviorSanitizer findings fatal in every run of the target (the fuzz build
/// compiles with recoverable checks, which would only print), so libFuzzer saves the input.
// NOLINTNEXTLINE(readability-identifier-naming,bugprone-reserved-identifier): the sanitizer's hook
extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:print_stacktrace=1";
}
