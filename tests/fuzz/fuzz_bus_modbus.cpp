// libFuzzer target for a bus of servos speaking Modbus RTU (docs/modbus.md): DYNAMIXEL-P and an
// RH-P12-RN(A) with Protocol Type 10, two of them sharing an address, fed the fuzz input as a
// client's byte chunks (fuzz_input.hpp) at fuzzer-chosen times, with every event due run on the
// virtual clock. Each chunk's gap is the silence after the chunk before has left the line, so
// that t1.5 and t3.5 fall on exact gap values. Checks what fuzz_bus checks (bus_invariants.hpp:
// every item within its range; every delivery well formed, colliding only while the bus counts
// an ID conflict) and, for each Modbus delivery, that it answers the request heard last as
// docs/modbus.md says (modbus_replies.hpp): no reply to broadcast or to a bad CRC, the normal
// response of the request's function or an exception 1 ~ 4, from the request's address 1 ~ 247.
// A servo switched to Protocol 2.0 over Modbus is checked as on the DYNAMIXEL bus.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "bus/bus.hpp"
#include "bus/line_timing.hpp"
#include "bus/loopback_link.hpp"
#include "bus_invariants.hpp"
#include "fuzz_input.hpp"
#include "modbus_segments.hpp"
#include "model/servo.hpp"
#include "repair_checks.hpp"
#include "shipped_model.hpp"
#include "sim/scheduler.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::fuzz::modbus_bus {

using sim::SimDuration;
using sim::SimTime;
using namespace std::chrono_literals;

// The client's line rate and the bus's reply timing, by bits 5-7 of the first byte. 0, which
// the hand-written seeds mostly use, is the servos' factory 57600 bit/s with modelled delays;
// 1 and 7 time replies as the daemon's fast and manual modes do, where the end of each write
// ends a frame; 9600 bit/s uses character times for t1.5 and t3.5, the others the fixed 750 and
// 1,750 us. The rates are those of the Baud Rate item, which a write may move a servo to.
struct Line {
  std::uint32_t bps;
  bus::ReplyTiming timing;
};
constexpr std::array<Line, 8> kLines = {{
    {57600, bus::ReplyTiming::Modelled},
    {57600, bus::ReplyTiming::Immediate},
    {9600, bus::ReplyTiming::Modelled},
    {115200, bus::ReplyTiming::Modelled},
    {1000000, bus::ReplyTiming::Modelled},
    {2000000, bus::ReplyTiming::Modelled},
    {4000000, bus::ReplyTiming::Modelled},
    {1000000, bus::ReplyTiming::Immediate},
}};

// Gaps: fine steps of 25 us below 128 (30: exactly the fixed t1.5 of 750 us, 70: the fixed t3.5
// of 1,750 us; up to 3.2 ms, past t3.5 at 9600 bit/s), coarse steps of 2 ms from 128 (replies,
// up to 256 ms: the longest read at 9600 bit/s); kGapToDeadline waits 1 s.
constexpr std::uint8_t kCoarseGaps = 128;
constexpr SimDuration kFineGapUnit = 25us;
constexpr SimDuration kCoarseGapUnit = 2ms;
constexpr SimDuration kLongestGap = 1s;

SimDuration gap_duration(std::uint8_t gap) {
  if (gap == kGapToDeadline) {
    return kLongestGap;
  }
  if (gap < kCoarseGaps) {
    return kFineGapUnit * gap;
  }
  return kCoarseGapUnit * (gap - kCoarseGaps + 1);
}

// After the input, the bus runs until nothing is due any more, but no longer than this.
constexpr SimDuration kDrain = 10s;

// Start away from zero, so that a time stamp of SimTime{} stands out as wrong.
constexpr SimTime kStart = sim::sim_time_from_ns(1'000'000'000);

// PH54-200-S500-R at 1, PM42-010-S260-R at 2, RH-P12-RN(A) at 247 (the highest Modbus address)
// and a second RH-P12-RN(A) at 2, whose replies collide with the PM42's and differ from them (a
// different Model Number, table and motion).
struct ModbusServo {
  const char* model;
  std::uint8_t id;
};
constexpr std::array<ModbusServo, 4> kServos = {{
    {"ph54-200-s500-r", 1},
    {"pm42-010-s260-r", 2},
    {"rh-p12-rna", 247},
    {"rh-p12-rna", 2},
}};

std::unique_ptr<model::Servo> make_servo(const ModbusServo& setup) {
  auto servo = std::make_unique<model::Servo>(test::shipped_model(setup.model), setup.id);
  servo->table().set("protocol_type", wire::traits(wire::Protocol::Modbus).type_value);
  servo->commit_deferred();
  return servo;
}

// One write of the client: `length` stream bytes from `begin`, arriving from `at`.
struct Write {
  SimTime at{};
  std::size_t begin = 0;
  std::size_t length = 0;
};

// Lays the chunks out on the line (each after the gap it asks for, counted from the moment the
// chunk before has left the line) and, for the repair flag, where the servos' framer cuts them.
std::vector<Write> plan_writes(const FuzzInput& input, std::size_t stream_size, const Line& line,
                               ModbusSegmenter& segmenter) {
  const bool immediate = line.timing == bus::ReplyTiming::Immediate;
  std::vector<Write> writes;
  SimTime line_free = kStart;
  std::size_t offset = 0;
  auto write = [&](std::uint8_t gap, std::size_t length) {
    Write w{line_free + gap_duration(gap), offset, std::min(length, stream_size - offset)};
    segmenter.advance(w.at);
    for (std::size_t k = 0; k < w.length; ++k) {
      // Bus::receive: a write's bytes follow each other a byte time apart, or all at once
      // without modelled delays.
      segmenter.byte(w.begin + k, immediate ? w.at : w.at + bus::wire_time(k, line.bps));
    }
    if (immediate && w.length > 0) {
      segmenter.end_of_write();
    }
    line_free = immediate ? w.at : w.at + bus::wire_time(w.length, line.bps);
    offset += w.length;
    writes.push_back(w);
  };
  for (const Chunk& chunk : input.chunks) {
    write(chunk.gap, chunk.length);
  }
  write(0, stream_size - offset);
  segmenter.close();
  return writes;
}

}  // namespace dxlemu::fuzz::modbus_bus

/// libFuzzer's entry point: one input, one fresh bus.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu;
  using namespace dxlemu::fuzz;
  using namespace dxlemu::fuzz::modbus_bus;
  const FuzzInput input = parse_fuzz_input(std::span(data, size));
  std::vector<std::uint8_t> stream(input.stream.begin(), input.stream.end());
  const Line line = kLines[input.spare];
  ModbusSegmenter segmenter(ModbusLine::at(line.bps));
  const std::vector<Write> writes = plan_writes(input, stream.size(), line, segmenter);
  if (input.repair_checks) {
    // 2.0 packets first, for servos switched to Protocol 2.0; then the Modbus frames' CRCs.
    constexpr std::array kV2 = {wire::Protocol::V2};
    repair_checks(stream, kV2);
    repair_modbus_crcs(stream, segmenter.segments());
  }

  sim::Scheduler scheduler;
  bus::LoopbackLink link;
  bus::Bus bus(scheduler, link);
  bus.set_reply_timing(line.timing);
  for (const ModbusServo& setup : kServos) {
    bus.add_servo(make_servo(setup));
  }
  RangeChecker ranges(bus);
  ranges.check();
  ReplyChecker checker(bus, link, [&ranges] { ranges.check(); });

  scheduler.advance_to(kStart);
  for (const Write& w : writes) {
    scheduler.advance_to(w.at);
    bus.receive(std::span(stream).subspan(w.begin, w.length), w.at, line.bps);
    ranges.check();
  }
  const SimTime drained = scheduler.now() + kDrain;
  while (const auto next = scheduler.next_deadline()) {
    if (*next > drained) {
      break;
    }
    scheduler.advance_to(*next);
  }
  bus.catch_up();
  ranges.check();
  checker.finish();
  return 0;
}
