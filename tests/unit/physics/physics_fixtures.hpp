#pragma once

#include <cstdint>
#include <numbers>
#include <string>

// What the physics tests share: the example world and an X servo's position units.
namespace dxlemu::test {

/// The shipped example world: a pendulum on one XM430-W350 (docs/physics.md).
inline const std::string kPendulum = std::string(DXLEMU_EXAMPLES_DIR) + "/physics/pendulum.xml";
/// Present Position of the pendulum's servo with the link level.
inline constexpr std::int64_t kLevel = 2048;
/// Position pulses of an X servo per radian of its shaft (4096 a turn).
inline constexpr double kPulsesPerRad = 4096 / (2 * std::numbers::pi);

}  // namespace dxlemu::test
