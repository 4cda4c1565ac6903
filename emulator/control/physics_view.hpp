#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "physics/world_clock.hpp"

namespace dxlemu::control {

/// A joint of the world driven by a servo: the config's "physics"/"joints" entry.
struct CoupledJoint {
  std::string joint;
  std::string port;
  std::uint8_t servo = 0;
};

/// What the control API sees of the physics world (docs/physics.md): its clock, which catches the
/// world up to a time, the MJCF it came from and which servo drives which joint.
struct PhysicsView {
  physics::WorldClock& clock;
  std::filesystem::path mjcf;
  std::vector<CoupledJoint> coupled;
};

}  // namespace dxlemu::control
