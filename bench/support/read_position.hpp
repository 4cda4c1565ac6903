#pragma once

#include <cstdint>
#include <vector>

#include "support/xm430.hpp"

namespace dxlemu::bench {

/// Where an XM430-W350 at factory settings stands when dxlemu starts it (its Present Position).
constexpr std::int32_t kStartPosition = 2048;

/// A Protocol 2.0 Read of Present Position from servo `id` (14 bytes), as a controller sends it.
std::vector<std::uint8_t> read_position_instruction(std::uint8_t id);

/// The 2.0 status (15 bytes) servo `id` standing at `position` answers that Read with: error 0,
/// the position little-endian.
std::vector<std::uint8_t> read_position_status(std::uint8_t id, std::int32_t position);

}  // namespace dxlemu::bench
