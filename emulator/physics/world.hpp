#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace dxlemu::physics {

/// One joint's state after a step, in the world's SI units.
struct JointState {
  double position_rad = 0;    ///< hinge angle (rad) or slide position (m)
  double velocity_rad_s = 0;  ///< rad/s (m/s for a slide)
};

/// A rigid-body world with joints that actuators push on: the seam between the servos and a
/// physics engine. It knows no servo, protocol or clock: the caller says when to step. Units are
/// SI (rad, rad/s, N·m, kg·m², s). Implementations must be deterministic: the same calls give the
/// same states bit for bit. docs/physics.md.
class World {
 public:
  virtual ~World() = default;

  /// The index of the one-degree-of-freedom joint (hinge or slide) called `name`, or nullopt.
  virtual std::optional<std::size_t> find_joint(std::string_view name) const = 0;
  /// The names of the joints find_joint() accepts, for error messages.
  virtual std::string joint_names() const = 0;
  /// The length of one step, s.
  virtual double timestep_s() const = 0;
  /// Adds rotor inertia seen at the joint (an actuator's gearbox), kg·m².
  virtual void add_armature(std::size_t joint, double kg_m2) = 0;
  /// The generalized force on `joint` for the following steps (N·m on a hinge), until set again.
  virtual void set_torque(std::size_t joint, double torque_nm) = 0;
  /// Advances one timestep.
  virtual void step() = 0;
  /// The joint now.
  virtual JointState joint(std::size_t joint) const = 0;
};

}  // namespace dxlemu::physics
