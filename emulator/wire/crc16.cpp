#include "wire/crc16.hpp"

namespace dxlemu::wire {
namespace {

constexpr std::uint16_t kPolynomial = 0x8005;

// The table is derived from the polynomial at compile time rather than pasted; a unit test
// compares it entry by entry with the table printed in protocol2-crc.md.
constexpr std::array<std::uint16_t, 256> make_table() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned i = 0; i < table.size(); ++i) {
    auto crc = static_cast<std::uint16_t>(i << 8);
    for (int bit = 0; bit < 8; ++bit) {
      const bool top = (crc & 0x8000U) != 0;
      crc = static_cast<std::uint16_t>(crc << 1);
      if (top) {
        crc ^= kPolynomial;
      }
    }
    table[i] = crc;
  }
  return table;
}

constexpr std::array<std::uint16_t, 256> kTable = make_table();

}  // namespace

const std::array<std::uint16_t, 256>& crc16_table() {
  return kTable;
}

std::uint16_t crc16_update(std::uint16_t crc, std::span<const std::uint8_t> bytes) {
  // protocol2-crc.md "Table-driven update": i = ((crc >> 8) ^ b) & 0xFF; crc = (crc << 8) ^
  // table[i].
  for (const std::uint8_t b : bytes) {
    const unsigned index = ((crc >> 8) ^ b) & 0xFFU;
    crc = static_cast<std::uint16_t>((crc << 8) ^ kTable[index]);
  }
  return crc;
}

}  // namespace dxlemu::wire
