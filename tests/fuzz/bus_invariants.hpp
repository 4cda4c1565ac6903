#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <set>
#include <span>
#include <vector>

#include "bus/bus.hpp"
#include "bus/loopback_link.hpp"
#include "feetech_replies.hpp"
#include "modbus_replies.hpp"
#include "model/servo.hpp"
#include "sim/sim_time.hpp"
#include "wire/frame.hpp"
#include "wire/protocol.hpp"

// What fuzz_bus checks about a bus without fault injection, kept apart from the input handling.
namespace dxlemu::fuzz {

/// True when `value` is one the model allows for item `item` of `servo` (its min/max and values),
/// or one of the documented values the device itself writes outside that range.
bool item_value_allowed(const model::Servo& servo, std::size_t item, std::int64_t value);

/// Checks that every item of every servo holds a value its model allows (model files' min/max and
/// values) at the moment it takes it: after each packet the bus hears (ReplyChecker's hook), after
/// each chunk and at the end. An item is decoded and checked only when its bytes changed since the
/// last check, which also keeps a value the servo accepted earlier from being judged again by
/// rules that changed since: Goal Position keeps a multi-turn goal when the Operating Mode is
/// switched away from Extended Position (the e-Manual's list of what a mode switch resets does not
/// name it; docs/motion.md), and such a goal is out of range only for the new mode.
class RangeChecker {
 public:
  /// Watches the servos `bus` has now; `bus` must outlive it.
  explicit RangeChecker(const bus::Bus& bus) : bus_(bus), seen_(bus.servos().size()) {}

  /// Aborts on the first item of any servo whose bytes changed to a value it may not hold.
  void check();

 private:
  void check_servo(const model::Servo& servo, std::vector<std::uint8_t>& seen);

  const bus::Bus& bus_;
  std::vector<std::vector<std::uint8_t>> seen_;  ///< per servo: its bytes at the last check
};

/// Watches a bus (as its LineObserver) and aborts on the first delivery to the client that
/// docs/bus.md does not allow. Allowed: one well-formed status packet of a protocol some servo
/// spoke, from an ID some servo had, with a valid error byte; or the Fast Sync/Bulk Read reply to
/// a request heard, whole or cut short after a block, every block in request order with its
/// running CRC; or, only while the bus counts an ID conflict not yet accounted for, colliding
/// replies (the AND of several packets, which keeps the header). On a FEETECH bus each delivery
/// must moreover be an answer FeetechReplies allows to the packet heard last, and each delivery of
/// servos speaking Modbus RTU one ModbusReplies allows to the request heard last.
class ReplyChecker {
 public:
  /// Installs itself as `bus`'s observer; both must outlive it. `before_packet`, when given, runs
  /// each time the bus hears a packet, before the servos handle it: it sees the state the packet
  /// before left.
  ReplyChecker(bus::Bus& bus, const bus::LoopbackLink& link,
               std::function<void()> before_packet = {});

  /// Checks that every delivery the link recorded went through the checks.
  void finish() const;

 private:
  struct Block {
    std::uint8_t id;
    std::uint16_t length;
  };
  using Layout = std::vector<Block>;

  void heard(const wire::FramerEvent& event);
  void sent(std::span<const std::uint8_t> bytes, sim::SimTime at, wire::Protocol protocol);
  bool is_status(std::span<const std::uint8_t> bytes, wire::Protocol protocol) const;
  bool is_fast_reply(std::span<const std::uint8_t> bytes);
  void remember_servos();

  const bus::Bus& bus_;
  const bus::LoopbackLink& link_;
  std::function<void()> before_packet_;
  std::size_t checked_ = 0;
  sim::SimTime last_delivery_{};
  // Replies still due: everything since the last instruction that cancelled them.
  std::uint64_t collisions_seen_ = 0;
  std::uint64_t conflicts_base_ = 0;  // ID conflicts counted before the replies still due
  std::uint64_t excused_ = 0;         // colliding deliveries accepted since then
  std::set<std::uint8_t> ids_;
  std::set<wire::Protocol> protocols_;
  std::vector<Layout> fast_requests_;
  FeetechReplies feetech_;
  ModbusReplies modbus_;
};

}  // namespace dxlemu::fuzz
