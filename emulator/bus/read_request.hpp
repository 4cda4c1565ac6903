#pragma once

#include <cstdint>
#include <vector>

#include "wire/instruction.hpp"

namespace dxlemu::bus {

/// One device's part of a Sync/Bulk Read, in request order.
struct ReadPart {
  std::uint8_t id = 0;
  std::uint16_t address = 0;
  std::uint16_t length = 0;
};

/// What a Sync, Bulk, Fast Sync or Fast Bulk Read asks of the devices it lists.
struct ReadRequest {
  bool fast = false;     ///< Fast Sync/Bulk Read: one combined reply from ID 0xFE
  bool v1_bulk = false;  ///< Protocol 1.0 Bulk Read (only some models execute it)
  /// The listed devices' parts, each ID once (the first listed; protocol1.md "Bulk Read": "If an
  /// identical ID is designated multiple times, only the first designated parameter will be
  /// processed"). A servo handles a packet once, so Sync Read too.
  std::vector<ReadPart> parts;
};

/// The read `packet` asks for; no parts when it is not a group read.
ReadRequest read_request(const wire::InstructionPacket& packet);

/// True for the instruction bytes of `protocol` that are only heard from the broadcast ID and list
/// the devices they address: DYNAMIXEL's Sync/Bulk Read/Write and their Fast forms, FEETECH's
/// SYNC READ (0x82) and SYNC WRITE (0x83).
bool is_group_instruction(wire::Protocol protocol, std::uint8_t code);

}  // namespace dxlemu::bus
