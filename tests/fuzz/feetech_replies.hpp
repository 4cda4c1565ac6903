#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <vector>

#include "bus/bus.hpp"
#include "sim/sim_time.hpp"
#include "wire/frame.hpp"

// What a FEETECH bus without injected faults may send back, packet by packet, as docs/feetech.md
// "On a bus" describes the servos: kept apart from ReplyChecker, which holds what every bus shares.
namespace dxlemu::fuzz {

/// The answers a FEETECH bus may give to the last packet it heard, in the order they may come:
/// one status to a unicast instruction its servo's Response level answers (none to Restart, to a
/// SYNC READ or SYNC WRITE not sent to 0xFE, or at level 0 to anything but READ and PING); one to
/// a broadcast PING (colliding bytes when several servos hear it); one per listed ID, in request
/// order and stopping at the first silent one, to a SYNC READ; none to any other broadcast.
/// docs/feetech.md "Refusals": no status to a bad checksum, an unknown or malformed instruction
/// (position calibration on SCS included), or a READ or SYNC READ part reaching past the
/// servo's table. Each status carries the addressed ID, all of a read's data or none, and only
/// the series' protection bits (voltage, overheat and, except on HLS, load; the angle sensor and
/// current bits only come from injected faults): no refusal sets a bit.
class FeetechReplies {
 public:
  /// Replaces what may be answered by the answers to `event`, a FEETECH frame or bad-check packet
  /// the bus is about to handle (both cancel the replies still due: docs/bus.md "Collisions"),
  /// judged on the servos' IDs and Response levels now, before they execute it.
  void heard(const wire::FramerEvent& event, const bus::Bus& bus);

  /// Checks `bytes`, delivered at `at`, against the next answer allowed and aborts if it is not
  /// one. `conflict_pending`: the bus has counted an ID conflict not yet accounted for, so the
  /// bytes may be colliding statuses where several servos share the answer. Returns true when the
  /// delivery used that conflict.
  bool check(std::span<const std::uint8_t> bytes, sim::SimTime at, bool conflict_pending);

 private:
  /// One status that may come: from `id` (kBroadcastId: any servo's, for a broadcast PING),
  /// possibly from `senders` servos at once.
  struct Answer {
    std::uint8_t id = 0;
    std::size_t senders = 0;
    std::uint16_t read_length = 0;  ///< the data of a read; 0 for other instructions
  };

  void expect_frame(const wire::Frame& frame, const bus::Bus& bus);
  /// The servos with `id` that answer: at their Response level, and by `answers`.
  std::size_t servos_with(std::uint8_t id, const bus::Bus& bus, bool answered_at_level_0,
                          const std::function<bool(const model::Servo&)>& answers) const;
  bool matches(const Answer& answer, std::span<const std::uint8_t> bytes) const;

  std::vector<Answer> answers_;
  std::size_t next_ = 0;
  sim::SimTime after_{};  ///< no delivery at or before: the packet, then the one before
  std::map<std::uint8_t, std::uint8_t> protection_bits_;  ///< per ID: the bits its servos may set
};

}  // namespace dxlemu::fuzz
