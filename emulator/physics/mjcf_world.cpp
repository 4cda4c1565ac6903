#include "physics/mjcf_world.hpp"

#ifdef DXLEMU_HAVE_MUJOCO
#include "physics/mujoco_world.hpp"
#endif

namespace dxlemu::physics {

#ifdef DXLEMU_HAVE_MUJOCO

bool mujoco_available() {
  return true;
}

std::string physics_engine() {
  return MujocoWorld::engine();
}

std::unique_ptr<World> load_mjcf_world(const std::filesystem::path& file, double timestep_s) {
  return std::make_unique<MujocoWorld>(file, timestep_s);
}

#else

bool mujoco_available() {
  return false;
}

std::string physics_engine() {
  return "no physics engine";
}

std::unique_ptr<World> load_mjcf_world(const std::filesystem::path& /*file*/,
                                       double /*timestep_s*/) {
  throw PhysicsError(
      "this build of dxlemu has no MuJoCo, so it cannot simulate physics: install Debian's "
      "libmujoco-dev and configure with -DDXLEMU_MUJOCO=ON (docs/physics.md)");
}

#endif

}  // namespace dxlemu::physics
