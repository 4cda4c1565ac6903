#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "physics/world.hpp"

struct mjModel_;
struct mjData_;

namespace dxlemu::physics {

/// The World of an MJCF model simulated by MuJoCo (built only with DXLEMU_MUJOCO). Joints are the
/// model's hinge and slide joints by name; torques go into qfrc_applied; one step is one
/// mj_step. MuJoCo types stay in the .cpp.
class MujocoWorld : public World {
 public:
  /// Loads `file` and sets its timestep to `timestep_s`. Throws PhysicsError with MuJoCo's
  /// message when the file does not load.
  MujocoWorld(const std::filesystem::path& file, double timestep_s);
  ~MujocoWorld() override;
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  /// "MuJoCo X.Y.Z" of the library linked.
  static std::string engine();

  std::optional<std::size_t> find_joint(std::string_view name) const override;
  std::vector<std::string> joints() const override;
  std::optional<std::size_t> find_body(std::string_view name) const override;
  std::vector<std::string> bodies() const override;
  double timestep_s() const override;
  void add_armature(std::size_t joint, double kg_m2) override;
  void set_torque(std::size_t joint, double torque_nm) override;
  void set_external_torque(std::size_t joint, double torque_nm) override;
  void set_wrench(std::size_t body, const Wrench& wrench) override;
  Wrench wrench(std::size_t body) const override;
  void step() override;
  JointState joint(std::size_t joint) const override;
  JointForces forces(std::size_t joint) const override;
  Scene scene() const override { return scene_; }
  std::vector<GeomPose> geom_poses() override;

 private:
  // scene_ and what geom_poses() needs, from the model's geoms.
  void describe_geoms();
  // qfrc_applied of a degree of freedom: the actuator's torque plus the external one.
  void apply(std::size_t dof);

  mjModel_* model_ = nullptr;
  mjData_* data_ = nullptr;
  // Per degree of freedom, the two parts of qfrc_applied.
  std::vector<double> actuator_;
  std::vector<double> external_;
  // The geoms drawn: scene_.geoms[i] is MuJoCo's geom drawn_[i], whose drawn shape's centre is
  // centre_[i] in the geom's frame (not zero for a mesh: its bounding box is off its origin).
  Scene scene_;
  std::vector<int> drawn_;
  std::vector<std::array<double, 3>> centre_;
};

}  // namespace dxlemu::physics
