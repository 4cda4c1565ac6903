#pragma once

#include <cstdint>
#include <vector>

namespace dxlemu::bus {

/// What the client receives when `packets` are sent at the same moment by servos that share an
/// ID: the line idles high and a 0 bit wins, so the bitwise AND of them, as long as the longest
/// (docs/bus.md "Collisions").
std::vector<std::uint8_t> collide(const std::vector<std::vector<std::uint8_t>>& packets);

}  // namespace dxlemu::bus
