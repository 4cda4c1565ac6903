// libFuzzer target for Modbus RTU's framing and codec (fuzz_wire.cpp's invariants assume frames
// that announce their LENGTH; Modbus RTU frames end at a silence). The input (fuzz_input.hpp) is
// a client's byte stream cut into chunks; each chunk's bytes follow each other on the line at the
// line rate bits 5-7 of the first byte choose, and its gap is the silence before it, measured
// from the end of the last byte of the chunk before (kModbusGap*), or the end of the client's
// write (kGapEndOfWrite). Two framers hear it: one is asked to expire() before each chunk, the
// other only fed; both must yield exactly the events ModbusSegmenter, a reference of the RTU
// framing rules written from the spec, expects, accounting for every byte fed. Every frame
// goes through the request decoder and the status decoder; a decoded request re-encodes to a
// request that decodes to the same instruction, and its responses (normal, with random table
// bytes, and exceptions) frame back as one frame each. Broken invariants abort, so libFuzzer
// saves the input.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "fuzz_input.hpp"
#include "fuzz_require.hpp"
#include "modbus_segments.hpp"
#include "sim/sim_time.hpp"
#include "wire/crc16_modbus.hpp"
#include "wire/describe.hpp"
#include "wire/frame.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::fuzz::modbus_wire {

using sim::SimDuration;
using sim::SimTime;
using wire::Frame;
using wire::FramerEvent;
using wire::FramingError;
using wire::FramingErrorKind;
using wire::Protocol;

constexpr Protocol kModbus = Protocol::Modbus;

// The client's line rate, by bits 5-7 of the first byte. 0, which the generated seeds have
// unless they say otherwise, is the DYNAMIXEL-P's factory 57600 bit/s (fixed 1,750/750 us
// silences above 19,200 bit/s); 9600, 19200, 1200 and 38400 use character times (19200 is the
// last rate that does); 0 bit/s is a rate the framer was never told (fixed silences, no byte
// time).
constexpr std::array<std::uint32_t, 8> kRates = {57600,  9600, 19200,   0,
                                                 115200, 1200, 1000000, 38400};

// Gap values below kModbusGapSplit are in 64ths of t1.5 (64: exactly t1.5, still one frame; 65
// breaks it), from it in 64ths of t3.5 counted from 64 (128: exactly t3.5, which ends the frame;
// 127 is just under twice t1.5, 6/7 of t3.5).
constexpr std::uint8_t kModbusGapSplit = 128;
constexpr std::int64_t kGapSteps = 64;

// Start the clock away from zero so that a time stamp of SimTime{} in an event stands out.
constexpr SimTime kStart = sim::sim_time_from_ns(1'000'000'000);
// "Far in the future" for the final expire(): beyond any silence, however many gaps came before.
constexpr SimDuration kFarFuture = std::chrono::hours(24);
constexpr std::size_t kCrcBytes = 2;
constexpr std::uint8_t kExceptionBit = 0x80;
constexpr std::uint8_t kLastExceptionCode = 4;

SimDuration quiet_before(std::uint8_t gap, const ModbusLine& line) {
  if (gap < kModbusGapSplit) {
    return line.gap * gap / kGapSteps;
  }
  return line.silence * (gap - kGapSteps) / kGapSteps;
}

// One feed: `length` stream bytes from `begin`, the first at `at`, the others a byte time apart;
// `end_of_write`: the client's write ended before them.
struct Step {
  SimTime at{};
  std::size_t begin = 0;
  std::size_t length = 0;
  bool end_of_write = false;
};

struct Plan {
  std::vector<Step> steps;
  std::vector<ModbusSegment> segments;
};

// Lays the input's chunks out on the line and cuts the stream into segments as the RTU rules do.
Plan plan_line(const FuzzInput& input, std::size_t stream_size, const ModbusLine& line) {
  Plan plan;
  ModbusSegmenter segmenter(line);
  SimTime line_free = kStart;  // when the last byte so far has left the line
  std::size_t offset = 0;
  auto step = [&](std::uint8_t gap, std::size_t length) {
    Step s;
    s.begin = offset;
    s.length = std::min(length, stream_size - offset);
    if (gap == kGapEndOfWrite) {
      s.end_of_write = true;
      s.at = line_free;
      segmenter.end_of_write();
    } else if (gap == kGapToDeadline) {
      s.at = segmenter.deadline().value_or(line_free);
    } else {
      s.at = line_free + quiet_before(gap, line);
    }
    segmenter.advance(s.at);
    for (std::size_t k = 0; k < s.length; ++k) {
      segmenter.byte(s.begin + k, s.at + line.byte_time * static_cast<std::int64_t>(k));
    }
    line_free = s.at + line.byte_time * static_cast<std::int64_t>(s.length);
    offset += s.length;
    plan.steps.push_back(s);
  };
  for (const Chunk& chunk : input.chunks) {
    step(chunk.gap, chunk.length);
  }
  step(0, stream_size - offset);
  segmenter.close();
  plan.segments = segmenter.segments();
  return plan;
}

// The event the framer must yield for `s`, built from the spec's rules rather than its code.
FramerEvent expected_event(const ModbusSegment& s, std::span<const std::uint8_t> stream) {
  const wire::FrameShape& shape = wire::traits(kModbus).frame;
  const std::size_t kept = std::min(s.size, ModbusSegmenter::kKeptBytes);
  const auto bytes = stream.subspan(s.begin, kept);
  const std::vector<std::uint8_t> raw(bytes.begin(), bytes.end());
  const bool sized = modbus_frame_size(s);
  if (sized && wire::crc16_modbus(bytes) == 0) {  // a frame with its CRC appended checks to 0
    Frame f;
    f.protocol = kModbus;
    f.id = raw[0];
    f.instruction = raw[1];
    f.params.assign(raw.begin() + 2, raw.end() - kCrcBytes);
    f.raw = raw;
    f.first_byte_at = s.first_at;
    f.last_byte_at = s.last_kept_at;
    f.offset = s.begin;
    return f;
  }
  FramingError e;
  e.kind = sized                                   ? FramingErrorKind::BadCheck
           : s.broken || s.size < shape.min_length ? FramingErrorKind::Truncated
                                                   : FramingErrorKind::ImpossibleLength;
  e.protocol = kModbus;
  e.bytes = s.size;
  e.id = raw[0];
  if (raw.size() > 1) {
    e.instruction = raw[1];
  }
  e.at = s.first_at;
  e.offset = s.begin;
  e.raw = raw;
  return e;
}

// Frames `bytes` with a fresh framer, ended by silence or by the end of the write; they must be
// exactly one frame and nothing else.
Frame reframe(const std::vector<std::uint8_t>& bytes, bool by_end_of_write) {
  wire::Framer framer(kModbus);
  std::vector<FramerEvent> events;
  framer.feed(bytes, kStart, events);
  if (by_end_of_write) {
    framer.end_of_write(events);
  } else {
    framer.expire(kStart + kFarFuture, events);
  }
  FUZZ_REQUIRE(events.size() == 1);
  const Frame* frame = std::get_if<Frame>(&events.front());
  FUZZ_REQUIRE(frame != nullptr);
  FUZZ_REQUIRE(frame->raw == bytes);
  return *frame;
}

// Table bytes for a normal response, derived from the frame so that they vary with the input.
std::vector<std::uint8_t> table_bytes(const Frame& frame, std::size_t count) {
  std::vector<std::uint8_t> out(count);
  const std::uint8_t seed = frame.raw[frame.raw.size() - 1];
  for (std::size_t i = 0; i < count; ++i) {
    out[i] = static_cast<std::uint8_t>(frame.raw[i % frame.raw.size()] * 31U + seed + i);
  }
  return out;
}

// An exception response to `frame` (code 1 ~ 4, picked by the frame) frames back as 5 bytes.
void check_exception(const Frame& frame, const wire::Instruction* request) {
  const auto code =
      static_cast<std::uint8_t>(1 + frame.raw[frame.raw.size() - 2] % kLastExceptionCode);
  const std::vector<std::uint8_t> bytes =
      wire::encode_modbus_response(frame.id, frame.instruction, request, code, {});
  const Frame again = reframe(bytes, false);
  FUZZ_REQUIRE(again.raw.size() == 5);
  FUZZ_REQUIRE(again.id == frame.id);
  FUZZ_REQUIRE(again.instruction == (frame.instruction | kExceptionBit));
  FUZZ_REQUIRE(again.params == std::vector<std::uint8_t>{code});
  const auto status = wire::decode_status(again);
  FUZZ_REQUIRE(std::holds_alternative<wire::StatusPacket>(status));
  FUZZ_REQUIRE(std::get<wire::StatusPacket>(status).error == code);
}

// The normal response to a request that decoded: one frame, echoing what the function echoes and
// carrying the table bytes of a read as registers (high byte first).
void check_normal_response(const Frame& frame, const wire::Instruction& instruction) {
  const auto* read = std::get_if<wire::Read>(&instruction);
  const auto* write_read = std::get_if<wire::WriteRead>(&instruction);
  const std::size_t read_bytes = read != nullptr         ? read->length
                                 : write_read != nullptr ? write_read->read.length
                                                         : 0;
  const std::vector<std::uint8_t> table = table_bytes(frame, read_bytes);
  const std::vector<std::uint8_t> bytes =
      wire::encode_modbus_response(frame.id, frame.instruction, &instruction, 0, table);
  const Frame again = reframe(bytes, true);
  FUZZ_REQUIRE(again.id == frame.id);
  FUZZ_REQUIRE(again.instruction == frame.instruction);
  const std::uint8_t function = frame.instruction;
  using wire::ModbusFunction;
  if (read != nullptr || write_read != nullptr) {
    FUZZ_REQUIRE(again.params.size() == 1 + read_bytes);
    FUZZ_REQUIRE(again.params[0] == read_bytes);
    for (std::size_t i = 0; i + 1 < read_bytes; i += 2) {
      FUZZ_REQUIRE(again.params[1 + i] == table[i + 1]);
      FUZZ_REQUIRE(again.params[2 + i] == table[i]);
    }
  } else if (function == wire::to_byte(ModbusFunction::WriteSingleRegister) ||
             function == wire::to_byte(ModbusFunction::Diagnostics)) {
    // Write Single Register and Return Query Data echo the request.
    FUZZ_REQUIRE(bytes == frame.raw);
  } else {
    // Write Multiple Registers: address, function, start and quantity.
    FUZZ_REQUIRE(function == wire::to_byte(ModbusFunction::WriteMultipleRegisters));
    FUZZ_REQUIRE(bytes.size() == 8);
    FUZZ_REQUIRE(std::equal(bytes.begin(), bytes.begin() + 6, frame.raw.begin()));
  }
}

void check_request(const Frame& frame) {
  const auto decoded = wire::decode_modbus_request(frame);
  FUZZ_REQUIRE(wire::decode_instruction(frame) == decoded);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    FUZZ_REQUIRE(error->id == frame.id);
    FUZZ_REQUIRE(error->instruction == frame.instruction);
    FUZZ_REQUIRE(!error->reason.empty());
    FUZZ_REQUIRE(error->kind == wire::DecodeErrorKind::BadLength ||
                 error->kind == wire::DecodeErrorKind::BadValue ||
                 error->kind == wire::DecodeErrorKind::BadAddress);
    check_exception(frame, nullptr);
    return;
  }
  const auto& packet = std::get<wire::InstructionPacket>(decoded);
  FUZZ_REQUIRE(packet.protocol == kModbus);
  FUZZ_REQUIRE(packet.id == frame.id);
  FUZZ_REQUIRE(!wire::describe(packet).empty());
  // Not caught on purpose: a decoded request the encoder refuses is a codec bug.
  const std::vector<std::uint8_t> bytes = wire::encode_modbus_request(packet);
  FUZZ_REQUIRE(wire::encode_instruction(packet) == bytes);
  const auto function = wire::modbus_function_of(packet.instruction);
  FUZZ_REQUIRE(function.has_value());
  if (*function == frame.instruction) {
    // One layout per function: the request comes back byte for byte.
    FUZZ_REQUIRE(bytes == frame.raw);
  }
  // Otherwise a 04 read comes back as 03, a one-register 16 write as 06: the same instruction.
  const auto again = wire::decode_modbus_request(reframe(bytes, false));
  const auto* packet_again = std::get_if<wire::InstructionPacket>(&again);
  FUZZ_REQUIRE(packet_again != nullptr);
  FUZZ_REQUIRE(*packet_again == packet);
  check_exception(frame, &packet.instruction);
  if (!std::holds_alternative<wire::UnknownInstruction>(packet.instruction)) {
    check_normal_response(frame, packet.instruction);
  }
}

void check_frame(const Frame& frame, SimTime now) {
  const wire::FrameShape& shape = wire::traits(kModbus).frame;
  FUZZ_REQUIRE(frame.protocol == kModbus);
  FUZZ_REQUIRE(frame.raw.size() >= shape.min_length && frame.raw.size() <= shape.max_length);
  const std::span<const std::uint8_t> raw(frame.raw);
  const std::uint16_t crc = wire::crc16_modbus(raw.first(raw.size() - kCrcBytes));
  FUZZ_REQUIRE(raw[raw.size() - 2] == (crc & 0xFFU) && raw[raw.size() - 1] == (crc >> 8));
  FUZZ_REQUIRE(frame.id == raw[0] && frame.instruction == raw[1]);
  FUZZ_REQUIRE(frame.params.size() + 2 + kCrcBytes == raw.size());
  FUZZ_REQUIRE(kStart <= frame.first_byte_at && frame.first_byte_at <= frame.last_byte_at);
  FUZZ_REQUIRE(frame.last_byte_at <= now);
  check_request(frame);
  const auto status = wire::decode_status(frame);
  if (const auto* s = std::get_if<wire::StatusPacket>(&status)) {
    FUZZ_REQUIRE(s->id == frame.id);
    FUZZ_REQUIRE(!wire::describe(*s).empty());
  }
}

// Everything one framer yielded, and the bytes its events covered.
struct Heard {
  std::vector<FramerEvent> events;
  std::uint64_t accounted = 0;
};

void check_events(std::span<const FramerEvent> events, const wire::Framer& framer, SimTime now,
                  Heard& heard) {
  for (const FramerEvent& event : events) {
    // Events cover the stream in order, each from where the one before ended.
    FUZZ_REQUIRE(wire::offset_of(event) == heard.accounted);
    if (const auto* frame = std::get_if<Frame>(&event)) {
      check_frame(*frame, now);
      heard.accounted += frame->raw.size();
    } else {
      const auto& error = std::get<FramingError>(event);
      FUZZ_REQUIRE(error.kind != FramingErrorKind::Garbage);  // no searching for a header here
      FUZZ_REQUIRE(error.bytes > 0 && error.at <= now);
      heard.accounted += error.bytes;
    }
    heard.events.push_back(event);
  }
  FUZZ_REQUIRE(heard.accounted + framer.buffered() <= framer.fed());
  FUZZ_REQUIRE(framer.deadline().has_value() == (framer.buffered() > 0));
}

}  // namespace dxlemu::fuzz::modbus_wire

/// libFuzzer's entry point: one input, two fresh framers.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu::fuzz;
  using namespace dxlemu::fuzz::modbus_wire;
  const FuzzInput input = parse_fuzz_input(std::span(data, size));
  std::vector<std::uint8_t> stream(input.stream.begin(), input.stream.end());
  const std::uint32_t bps = kRates[input.spare];
  const ModbusLine line = ModbusLine::at(bps);
  const Plan plan = plan_line(input, stream.size(), line);
  if (input.repair_checks) {
    repair_modbus_crcs(stream, plan.segments);
  }

  // `expiring` is asked to expire() before each chunk, as the bus's timer does; `fed` only
  // hears bytes, so it ends a frame when the first byte after the silence comes.
  dxlemu::wire::Framer expiring(kModbus);
  dxlemu::wire::Framer fed(kModbus);
  expiring.set_line_rate(bps);
  fed.set_line_rate(bps);
  Heard heard_expiring;
  Heard heard_fed;
  std::vector<FramerEvent> events;
  SimTime now = kStart;
  std::vector<SimTime> times;
  for (const Step& step : plan.steps) {
    const std::span<const std::uint8_t> chunk(stream.data() + step.begin, step.length);
    times.resize(step.length);
    for (std::size_t k = 0; k < step.length; ++k) {
      times[k] = step.at + line.byte_time * static_cast<std::int64_t>(k);
    }
    now = step.length > 0 ? times.back() : step.at;
    for (auto [framer, heard] :
         {std::pair{&expiring, &heard_expiring}, std::pair{&fed, &heard_fed}}) {
      events.clear();
      if (step.end_of_write) {
        framer->end_of_write(events);
      }
      if (framer == &expiring && line.byte_time == SimDuration{0}) {
        framer->feed(chunk, step.at, events);  // expires, then feeds: every byte at step.at
      } else {
        if (framer == &expiring) {
          framer->expire(step.at, events);
        }
        framer->feed(chunk, times, events);
      }
      check_events(events, *framer, now, *heard);
    }
  }
  now += kFarFuture;
  for (auto [framer, heard] :
       {std::pair{&expiring, &heard_expiring}, std::pair{&fed, &heard_fed}}) {
    events.clear();
    framer->expire(now, events);
    check_events(events, *framer, now, *heard);
    FUZZ_REQUIRE(framer->buffered() == 0 && !framer->deadline().has_value());
    FUZZ_REQUIRE(framer->fed() == stream.size());
    FUZZ_REQUIRE(heard->accounted == stream.size());
  }

  // Both framers yield what the RTU rules make of the line, event for event.
  FUZZ_REQUIRE(heard_expiring.events.size() == plan.segments.size());
  for (std::size_t i = 0; i < plan.segments.size(); ++i) {
    FUZZ_REQUIRE_MSG(heard_expiring.events[i] == expected_event(plan.segments[i], stream),
                     "segment %zu: %zu bytes from %zu", i, plan.segments[i].size,
                     plan.segments[i].begin);
  }
  FUZZ_REQUIRE(heard_fed.events == heard_expiring.events);
  if (input.repair_checks) {
    for (const FramerEvent& event : heard_fed.events) {
      const auto* error = std::get_if<FramingError>(&event);
      FUZZ_REQUIRE(error == nullptr || error->kind != FramingErrorKind::BadCheck);
    }
  }
  return 0;
}

/// Makes UndefinedBehaviorSanitizer findings fatal in every run of the target (the fuzz build
/// compiles with recoverable checks, which would only print), so libFuzzer saves the input.
// NOLINTNEXTLINE(readability-identifier-naming,bugprone-reserved-identifier): the sanitizer's hook
extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:print_stacktrace=1";
}
