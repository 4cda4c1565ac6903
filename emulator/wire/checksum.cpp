#include "wire/checksum.hpp"

namespace dxlemu::wire {

std::uint8_t v1_checksum(std::span<const std::uint8_t> body) {
  unsigned sum = 0;
  for (const std::uint8_t b : body) {
    sum += b;
  }
  // "When the calculation result ... is larger than 255 (0xFF), use only lower bytes."
  return static_cast<std::uint8_t>(~sum & 0xFFU);
}

}  // namespace dxlemu::wire
