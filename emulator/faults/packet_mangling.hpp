#pragma once

#include <cstdint>
#include <vector>

#include "sim/rng.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::faults {

// Byte-level damage to status packets, as the wire faults of docs/faults.md apply it. Pure
// functions of their inputs (and of the stream they draw from).

/// Makes the CRC (2.0; Modbus RTU's CRC-16 too) or checksum (1.0) of `packet` wrong by inverting
/// its last byte. Nothing
/// happens to an empty packet.
void break_check(std::vector<std::uint8_t>& packet);

/// Inverts `bits` distinct bits of `bytes` at positions drawn from `stream` (every bit when there
/// are fewer than `bits`).
void flip_bits(std::vector<std::uint8_t>& bytes, std::uint32_t bits, sim::RandomStream& stream);

/// Rewrites the ID of status packet `packet` (of `protocol`; a Modbus response's address) to `id`
/// and recomputes its check, so that the client receives a valid packet from the wrong servo. A
/// packet too short to hold an ID is left alone.
void set_id(std::vector<std::uint8_t>& packet, wire::Protocol protocol, std::uint8_t id);

/// `count` bytes drawn from `stream`.
std::vector<std::uint8_t> random_bytes(std::size_t count, sim::RandomStream& stream);

}  // namespace dxlemu::faults
