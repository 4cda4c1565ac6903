#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bus/bus.hpp"
#include "bus/line_timing.hpp"
#include "bus/loopback_link.hpp"
#include "shipped_model.hpp"
#include "wire/describe.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::test {

/// The broadcast ID, short for the many group and broadcast packets of the bus tests.
inline constexpr std::uint8_t kBroadcast = wire::kBroadcastId;
/// XM430-W350 / XC330-T288 factory timing: processing 50 us, Return Delay Time 250 x 2 us.
inline constexpr sim::SimDuration kXProcessing = std::chrono::microseconds(50);
inline constexpr sim::SimDuration kXReturnDelay = std::chrono::microseconds(500);

/// A bus of shipped models on a hand-advanced clock, recording what reaches the client.
struct BusRig {
  static constexpr std::uint32_t kBaud = 57600;  // every shipped X model's factory rate

  sim::Scheduler scheduler;
  bus::LoopbackLink link;
  bus::Bus bus{scheduler, link};

  /// Adds a servo of the shipped model `name` with `id`.
  model::Servo& add(const std::string& name, std::uint8_t id) {
    return bus.add_servo(std::make_unique<model::Servo>(shipped_model(name), id));
  }
  /// The client writes `packet` now at `bps`; returns the instruction's size in bytes.
  std::size_t send(const wire::InstructionPacket& packet, std::uint32_t bps = kBaud) {
    const auto bytes = wire::encode_instruction(packet);
    bus.receive(bytes, scheduler.now(), bps);
    return bytes.size();
  }
  /// Lets simulated time pass (default: long enough for any reply).
  void run(sim::SimDuration d = std::chrono::seconds(1)) { scheduler.advance_by(d); }
};

/// Makes `servo` really turn (torque off, back-driven by an external load of `load_nm`; 0 stops
/// it): for rules that depend on Moving. Moving reads 1 from the first tick after.
inline void turn_by_hand(model::Servo& servo, double load_nm) {
  model::Conditions c = servo.motion().conditions();
  c.external_load_nm = load_nm;
  servo.motion().set_conditions(c);
}

/// The line time of `bytes` at the rig's baud rate.
/// `v` as the 4 little-endian bytes of a Protocol 2.0 item.
inline std::vector<std::uint8_t> le32(std::int64_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  return {static_cast<std::uint8_t>(u), static_cast<std::uint8_t>(u >> 8),
          static_cast<std::uint8_t>(u >> 16), static_cast<std::uint8_t>(u >> 24)};
}

inline sim::SimDuration line(std::size_t bytes, std::uint32_t bps = BusRig::kBaud) {
  return bus::wire_time(bytes, bps);
}

/// The describe() text of the one status packet in `bytes` ("id=1 error=0x00 params=FC 03 2D").
inline std::string status_text(const std::vector<std::uint8_t>& bytes,
                               wire::Protocol protocol = wire::Protocol::V2) {
  wire::Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, sim::SimTime{}, events);
  if (events.size() != 1 || !std::holds_alternative<wire::Frame>(events[0])) {
    return "not one status packet";
  }
  const auto status = wire::decode_status(std::get<wire::Frame>(events[0]));
  if (!std::holds_alternative<wire::StatusPacket>(status)) {
    return "not a status packet";
  }
  return wire::describe(std::get<wire::StatusPacket>(status));
}

}  // namespace dxlemu::test
