#include "bus/collision.hpp"

namespace dxlemu::bus {

std::vector<std::uint8_t> collide(const std::vector<std::vector<std::uint8_t>>& packets) {
  std::vector<std::uint8_t> out;
  for (const auto& p : packets) {
    if (out.size() < p.size()) {
      out.resize(p.size(), 0xFF);
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      out[i] &= p[i];
    }
  }
  return out;
}

}  // namespace dxlemu::bus
