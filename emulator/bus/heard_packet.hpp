#pragma once

#include <cstdint>

#include "sim/sim_time.hpp"
#include "wire/instruction.hpp"
#include "wire/protocol.hpp"
#include "wire/protocol_table.hpp"

namespace dxlemu::bus {

/// The packet a bus is handling, as its servos met it on the line: the context the bus passes
/// with every step of handling it, and to the fault hooks.
struct HeardPacket {
  wire::Protocol protocol = wire::kDefaultProtocol;
  std::uint8_t id = 0;           ///< the packet ID (unverified for a damaged packet)
  std::uint8_t instruction = 0;  ///< the instruction byte (unverified for a damaged packet)
  /// The decoded instruction; nullptr when the packet is damaged or could not be decoded.
  const wire::InstructionPacket* decoded = nullptr;
  sim::SimTime end{};  ///< when its last byte crossed the line
};

}  // namespace dxlemu::bus
