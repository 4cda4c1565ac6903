#pragma once

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "physics/world.hpp"

namespace dxlemu::physics {

/// An MJCF file that could not be loaded, or a build without a physics engine; the message is
/// the reason, without the file name (the caller names the file and the config field).
class PhysicsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// True when this build has MuJoCo (CMake option DXLEMU_MUJOCO).
bool mujoco_available();

/// "MuJoCo 2.2.2" in a build with it, else "no physics engine".
std::string physics_engine();

/// The world of the MJCF file `file`, stepping `timestep_s` seconds at a time (its own
/// `<option timestep>` is overridden). Throws PhysicsError when the file does not load or the
/// build has no MuJoCo.
std::unique_ptr<World> load_mjcf_world(const std::filesystem::path& file, double timestep_s);

}  // namespace dxlemu::physics
