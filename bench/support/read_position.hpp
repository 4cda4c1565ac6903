#pragma once

#include <cstdint>
#include <vector>

namespace dxlemu::bench {

/// The X series' Present Position: control table address 132, 4 bytes (e-Manual XM430-W350).
constexpr std::uint16_t kPresentPosition = 132;
constexpr std::uint16_t kPresentPositionSize = 4;
/// Where an XM430-W350 at factory settings stands when dxlemu starts it (its Present Position).
constexpr std::int32_t kStartPosition = 2048;

/// A Protocol 2.0 Read of Present Position from servo `id` (14 bytes), as a controller sends it.
std::vector<std::uint8_t> read_position_instruction(std::uint8_t id);

/// The 2.0 status (15 bytes) servo `id` standing at `position` answers that Read with: error 0,
/// the position little-endian.
std::vector<std::uint8_t> read_position_status(std::uint8_t id, std::int32_t position);

}  // namespace dxlemu::bench
