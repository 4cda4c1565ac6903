#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "bus/bus.hpp"
#include "sim/sim_time.hpp"
#include "wire/frame.hpp"
#include "wire/instruction_decoder.hpp"

// What a bus of Modbus RTU servos without injected faults may send back, request by request, as
// docs/modbus.md describes them: kept apart from ReplyChecker, which holds what every bus shares.
namespace dxlemu::fuzz {

/// The one answer a bus may give to the last Modbus request it heard: none to broadcast (address
/// 0), to an address no servo speaking Modbus has, or to a frame with a bad CRC; otherwise at most
/// one delivery, from the request's address (1 ~ 247), no earlier than the request's last byte:
/// the normal response of the request's function (a read's byte count and registers, the echo of
/// Write Single Register and Diagnostics, start and quantity of Write Multiple Registers), or an
/// exception response (function | 0x80, exception code 1 ~ 4; 01 for a function or sub-function
/// the servers do not serve), or, where several servos share the address, their colliding bytes.
class ModbusReplies {
 public:
  /// Replaces what may be answered by the answer to `event`, a frame or a bad-check packet of any
  /// protocol that the bus is about to handle (each cancels the replies still due: docs/bus.md
  /// "Collisions"), judged on the servos' addresses and protocols now, before they execute it.
  void heard(const wire::FramerEvent& event, const bus::Bus& bus);

  /// Checks `bytes`, a delivery of Modbus servos at `at`, against the answer allowed and aborts
  /// if it is not one. `conflict_pending`: the bus has counted an ID conflict not yet accounted
  /// for. Returns true when the delivery used that conflict.
  bool check(std::span<const std::uint8_t> bytes, sim::SimTime at, bool conflict_pending);

 private:
  bool normal_response(std::span<const std::uint8_t> bytes) const;
  bool exception_response(std::span<const std::uint8_t> bytes) const;

  /// The request still to be answered, what it decoded to, and how many servos have its address.
  std::optional<wire::Frame> request_;
  std::optional<wire::DecodeResult<wire::InstructionPacket>> decoded_;
  std::size_t senders_ = 0;
};

}  // namespace dxlemu::fuzz
