// libFuzzer target for a whole bus, built once per maker (a port speaks one maker's protocol,
// docs/feetech.md "One maker per port"): shipped models of several families, fed the fuzz input as
// a client's byte chunks arriving at fuzzer-chosen times (fuzz_input.hpp), with every event due run
// on the virtual clock. Checks that everything the client receives is what docs/bus.md, and on the
// FEETECH bus docs/feetech.md, allows (bus_invariants.hpp, feetech_replies.hpp) and that no
// control-table item ever leaves its range. No fault injection here: with faults, damaged replies
// are the point.
//
// DXLEMU_FUZZ_BUS_FEETECH (0 or 1) picks the bus: DYNAMIXEL (fuzz_bus) or FEETECH
// (fuzz_bus_feetech).

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bus/bus.hpp"
#include "bus/loopback_link.hpp"
#include "bus_invariants.hpp"
#include "fuzz_input.hpp"
#include "fuzz_require.hpp"
#include "model/servo.hpp"
#include "repair_checks.hpp"
#include "shipped_model.hpp"
#include "sim/scheduler.hpp"

#ifndef DXLEMU_FUZZ_BUS_FEETECH
#error "build fuzz_bus.cpp with -DDXLEMU_FUZZ_BUS_FEETECH=0 (DYNAMIXEL) or 1 (FEETECH)"
#endif

namespace dxlemu::fuzz {
namespace {

using sim::SimDuration;
using namespace std::chrono_literals;

constexpr bool kFeetech = DXLEMU_FUZZ_BUS_FEETECH != 0;

// The client's serial port speed, chosen by bits 5-7 of the input's first byte (the bits
// fuzz_input.hpp leaves free); index 0, which the generated seeds have, is the rate most of the
// bus's servos use. Servos hear only a client within 3 % of their own rate.
// DYNAMIXEL: the rates the bus's servos use (57600 most, 1 Mbps the AX-12A), rates a written Baud
// Rate can move them to, and one rate just inside the tolerance. FEETECH: the eight rates of the
// Baud rate codes 0 ~ 7 (docs/feetech.md "Models"), so that every rate a written code moves a
// servo to can be followed.
constexpr std::array<std::uint32_t, 8> kDynamixelClientBps = {57600,   1000000, 115200,  9600,
                                                              2000000, 56000,   3000000, 500000};
constexpr std::array<std::uint32_t, 8> kFeetechClientBps = {1000000, 500000, 250000, 128000,
                                                            115200,  76800,  57600,  38400};
constexpr std::array<std::uint32_t, 8> kClientBps =
    kFeetech ? kFeetechClientBps : kDynamixelClientBps;
constexpr unsigned kBaudShift = 5;

// Two ranges of gaps between chunks: fine steps around the 2.0 inter-byte timeout (1.5 ms) and
// the replies at 1 Mbps, coarse steps around the 1.0 and FEETECH timeout (100 ms) and replies at
// 57600 bps; the largest value outlasts a reboot (DYNAMIXEL 400 ms, FEETECH's Restart 1800 ms) and
// short Bus Watchdog periods.
constexpr std::uint8_t kCoarseGaps = 128;
constexpr SimDuration kFineGapUnit = 25us;
constexpr SimDuration kCoarseGapUnit = 2ms;
constexpr SimDuration kLongestGap = kFeetech ? 2s : 1s;

SimDuration gap_duration(std::uint8_t gap) {
  if (gap == kGapToDeadline) {
    return kLongestGap;
  }
  if (gap < kCoarseGaps) {
    return kFineGapUnit * gap;
  }
  return kCoarseGapUnit * (gap - kCoarseGaps + 1);
}

// After the input, the bus runs until nothing is due any more (replies, timeouts, watchdogs), but
// no longer than this: the longest read at 9600 bps from every servo in turn, plus the boot after
// a reboot. Running the whole 10 s every time made idle motion ticks a quarter of the target's
// time; the gaps between chunks still reach long times (kLongestGap).
constexpr SimDuration kDrain = 10s;

// One servo of the bus: a shipped model, its ID, and the Protocol Type and Baud Rate item values
// it starts with (nullopt: the model's default).
struct ServoSetup {
  const char* model = nullptr;
  std::uint8_t id = 0;
  std::optional<std::int64_t> protocol_type;
  std::optional<std::int64_t> baud_rate;
};

// Mixed on purpose: three families on 2.0 (X, XL-320, P), X in 1.0 mode, MX and AX on 1.0; all
// at 57600 bps except the AX-12A at its factory 1 Mbps. No PRO (H54): its 558 items would make
// every input a third slower to set up and check, for a family that behaves as P on the bus.
constexpr std::array<ServoSetup, 6> kDynamixelServos = {{
    {"xm430-w350", 1, std::nullopt, std::nullopt},
    {"xl-320", 2, std::nullopt, 1},  // 57600
    {"ph54-200-s500-r", 3, std::nullopt, std::nullopt},
    {"mx-28", 5, std::nullopt, std::nullopt},
    {"ax-12a", 6, std::nullopt, std::nullopt},
    {"xm430-w210", 7, 1, std::nullopt},  // Protocol 1.0
}};

// Every FEETECH series: STS (two STS3215 sharing ID 2, so that their statuses collide, as in the
// page's SYNC READ of IDs 1 and 2), SCS (the big-endian SCS0009), SMS and HLS, at the factory
// 1 Mbps, and an STS3250 at 500000 bps (code 1) that hears only a client at its rate. The IDs are
// those of FEETECH's example frames (1 ~ 10), which seed the target.
constexpr std::array<ServoSetup, 7> kFeetechServos = {{
    {"feetech/sts3215", 1, std::nullopt, std::nullopt},
    {"feetech/sts3215", 2, std::nullopt, std::nullopt},
    {"feetech/sts3215", 2, std::nullopt, std::nullopt},
    {"feetech/scs0009", 3, std::nullopt, std::nullopt},
    {"feetech/sm8512bl", 4, std::nullopt, std::nullopt},
    {"feetech/hls3625m", 5, std::nullopt, std::nullopt},
    {"feetech/sts3250", 6, std::nullopt, 1},  // 500000
}};

std::unique_ptr<model::Servo> make_servo(const ServoSetup& setup) {
  auto servo = std::make_unique<model::Servo>(test::shipped_model(setup.model), setup.id);
  if (setup.protocol_type) {
    servo->table().set("protocol_type", *setup.protocol_type);
  }
  if (setup.baud_rate) {
    servo->table().set("baud_rate", *setup.baud_rate);
  }
  servo->commit_deferred();
  return servo;
}

}  // namespace
}  // namespace dxlemu::fuzz

/// libFuzzer's entry point: one input, one fresh bus.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu;
  using namespace dxlemu::fuzz;
  const FuzzInput input = parse_fuzz_input(std::span(data, size));
  std::vector<std::uint8_t> stream(input.stream.begin(), input.stream.end());
  if (input.repair_checks) {
    constexpr std::array kDynamixel = {wire::Protocol::V1, wire::Protocol::V2};
    constexpr std::array kFeetechOnly = {wire::Protocol::Feetech};
    if constexpr (kFeetech) {
      repair_checks(stream, kFeetechOnly);
    } else {
      repair_checks(stream, kDynamixel);
    }
  }
  const std::uint32_t client_bps = kClientBps[size > 0 ? data[0] >> kBaudShift : 0];

  sim::Scheduler scheduler;
  bus::LoopbackLink link;
  bus::Bus bus(scheduler, link);
  auto add = [&bus](const auto& servos) {
    for (const ServoSetup& setup : servos) {
      bus.add_servo(make_servo(setup));
    }
  };
  if constexpr (kFeetech) {
    add(kFeetechServos);
  } else {
    add(kDynamixelServos);
  }
  RangeChecker ranges(bus);
  ranges.check();
  ReplyChecker checker(bus, link, [&ranges] { ranges.check(); });

  // Start away from zero, so that a time stamp of SimTime{} stands out as wrong.
  scheduler.advance_by(1s);
  std::size_t offset = 0;
  auto feed = [&](std::size_t length, SimDuration gap) {
    scheduler.advance_by(gap);
    bus.receive(std::span(stream).subspan(offset, length), scheduler.now(), client_bps);
    offset += length;
    ranges.check();
  };
  for (const Chunk& chunk : input.chunks) {
    feed(std::min<std::size_t>(chunk.length, stream.size() - offset), gap_duration(chunk.gap));
  }
  feed(stream.size() - offset, SimDuration{0});
  const sim::SimTime drained = scheduler.now() + kDrain;
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
