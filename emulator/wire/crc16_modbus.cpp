#include "wire/crc16_modbus.hpp"

#include <array>

namespace dxlemu::wire {
namespace {

constexpr std::uint16_t kReflectedPolynomial = 0xA001;
constexpr std::uint16_t kInitial = 0xFFFF;

// Byte-wise table of the reflected polynomial, derived at compile time.
constexpr std::array<std::uint16_t, 256> make_modbus_table() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned i = 0; i < table.size(); ++i) {
    auto crc = static_cast<std::uint16_t>(i);
    for (int bit = 0; bit < 8; ++bit) {
      const bool low = (crc & 1U) != 0;
      crc = static_cast<std::uint16_t>(crc >> 1);
      if (low) {
        crc ^= kReflectedPolynomial;
      }
    }
    table[i] = crc;
  }
  return table;
}

constexpr std::array<std::uint16_t, 256> kModbusTable = make_modbus_table();

}  // namespace

std::uint16_t crc16_modbus(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = kInitial;
  for (const std::uint8_t b : bytes) {
    crc = static_cast<std::uint16_t>((crc >> 8) ^ kModbusTable[(crc ^ b) & 0xFFU]);
  }
  return crc;
}

}  // namespace dxlemu::wire
