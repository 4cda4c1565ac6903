#pragma once

// The FEETECH helpers of the bus tests (feetech_*_test.cpp), on a BusRig. In a named namespace,
// each inline: the tests compile in unity batches, where two files' anonymous namespaces are one.

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bus_rig.hpp"
#include "model/servo.hpp"

namespace dxlemu::test::feetech {

/// Every FEETECH model's factory rate, 1 Mbps.
inline constexpr std::uint32_t kRate = 1'000'000;
/// The FEETECH models' processing time (no source gives one: docs/feetech.md "Reply timing").
inline constexpr sim::SimDuration kProcessing = std::chrono::microseconds(50);

/// Adds `count` STS3215 with IDs 1 ~ count to `rig`; returns `rig`.
inline BusRig& sts_bus(BusRig& rig, int count) {
  for (int id = 1; id <= count; ++id) {
    rig.add("feetech/sts3215", static_cast<std::uint8_t>(id));
  }
  return rig;
}

/// The client sends `instruction` to `id` now, in FEETECH framing at kRate; returns the packet's
/// size in bytes.
inline std::size_t send(BusRig& rig, std::uint8_t id, wire::Instruction instruction) {
  return rig.send({wire::Protocol::Feetech, id, std::move(instruction)}, kRate);
}

/// Sends and lets the reply (if any) come before the next packet (10 ms), as a client waits for
/// it.
inline void ask(BusRig& rig, std::uint8_t id, wire::Instruction instruction) {
  send(rig, id, std::move(instruction));
  rig.run(std::chrono::milliseconds(10));
}

/// The describe() text of the FEETECH status packet in `d` ("id=1 error=0x20 params=C8 00").
inline std::string status(const bus::LoopbackLink::Delivery& d) {
  return status_text(d.bytes, wire::Protocol::Feetech);
}

/// The last status the client got, as status() gives it, or "no reply" when it got none.
inline std::string last_status(const BusRig& rig) {
  const auto& d = rig.link.deliveries();
  return d.empty() ? "no reply" : status(d.back());
}

/// `v` as a FEETECH 2-byte item, low byte first (its low 16 bits, two's complement if negative).
inline std::vector<std::uint8_t> le16(std::int64_t v) {
  const auto u = static_cast<std::uint16_t>(v);
  return {static_cast<std::uint8_t>(u), static_cast<std::uint8_t>(u >> 8)};
}

/// `v` as FEETECH's sign-magnitude 2 bytes (bit 15 the sign), low byte first as on an STS.
inline std::vector<std::uint8_t> sm16(std::int64_t v) {
  const auto u = static_cast<std::uint16_t>(v < 0 ? (0x8000 | -v) : v);
  return {static_cast<std::uint8_t>(u), static_cast<std::uint8_t>(u >> 8)};
}

/// Blocks the servo's shaft (or frees it), at the supply it has.
inline void block_shaft(model::Servo& servo, bool blocked) {
  model::Conditions c = servo.motion().conditions();
  c.blocked = blocked;
  servo.motion().set_conditions(c);
}

/// Powers the servo at `volts`.
inline void set_supply(model::Servo& servo, double volts) {
  model::Conditions c = servo.motion().conditions();
  c.supply_v = volts;
  servo.motion().set_conditions(c);
}

/// The item `key` of `servo` as it is now (the motion caught up first).
inline std::int64_t item_now(BusRig& rig, model::Servo& servo, const std::string& key) {
  rig.bus.catch_up();
  return servo.table().get(key);
}

/// Turns the shaft by hand to where Present position reads `reading`, and runs 5 ms, for a tick
/// to absorb it. (test::turn_by_hand instead back-drives a shaft with a load.)
inline void turn_by_hand_to(BusRig& rig, model::Servo& servo, std::int64_t reading) {
  servo.table().set("present_position", reading);
  rig.run(std::chrono::milliseconds(5));
}

}  // namespace dxlemu::test::feetech
