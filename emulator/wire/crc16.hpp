#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace dxlemu::wire {

/// The 256-entry lookup table of the Protocol 2.0 CRC-16 (polynomial 0x8005, MSB first), equal to
/// the table printed in protocol2-crc.md. Entry i is the CRC of the single byte i.
const std::array<std::uint16_t, 256>& crc16_table();

/// Continues a Protocol 2.0 CRC-16 over `bytes`, starting from `crc` (0 for a new packet): initial
/// value 0, no reflection, no final XOR. Feeding a packet in pieces gives the same result as at
/// once.
std::uint16_t crc16_update(std::uint16_t crc, std::span<const std::uint8_t> bytes);

/// The Protocol 2.0 CRC-16 of `bytes` (everything from Header 1 through the last parameter).
inline std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  return crc16_update(0, bytes);
}

}  // namespace dxlemu::wire
