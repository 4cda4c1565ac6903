#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dxlemu::physics {

/// One joint's state after a step, in the world's SI units.
struct JointState {
  double position_rad = 0;    ///< hinge angle (rad) or slide position (m)
  double velocity_rad_s = 0;  ///< rad/s (m/s for a slide)
};

/// The generalized forces on one joint in the last step (N·m on a hinge, N on a slide).
struct JointForces {
  double actuator = 0;    ///< what set_torque() applied: the servo's drive
  double external = 0;    ///< what set_external_torque() applied: a push from outside
  double constraint = 0;  ///< what limits, contacts and equality constraints applied
  double bias = 0;        ///< gravity, Coriolis and centrifugal: what holding still must balance
};

/// A force and a torque on a body at its centre of mass, in world coordinates (N, N·m).
struct Wrench {
  std::array<double, 3> force{};
  std::array<double, 3> torque{};
};

/// The shapes a world's geoms have, as drawn (docs/control-api.md "physics.scene").
enum class GeomType { Plane, Sphere, Capsule, Ellipsoid, Cylinder, Box, Mesh };

/// One geom of the world as it is drawn: what never changes while the world runs.
struct GeomShape {
  std::string name;  ///< "" when the model names none
  std::string body;  ///< the body it belongs to ("" when unnamed)
  GeomType type = GeomType::Box;
  /// MuJoCo's geom_size: sphere [r], capsule and cylinder [r, half-length] (along the local z
  /// axis), ellipsoid and box the half-extents, plane [hx, hy, grid spacing] (0: infinite); a
  /// mesh the half-extents of its bounding box, which is what is drawn.
  std::array<double, 3> size{};
  std::array<double, 4> rgba{};  ///< its colour (its material's when it has one)
  std::string mesh;              ///< the mesh's name, for a mesh ("" when unnamed)
};

/// Where a drawn geom is: the centre of its shape and its rotation, world frame.
struct GeomPose {
  std::array<double, 3> pos{};
  std::array<double, 9> mat{};  ///< rotation, row-major: local axes are its columns
};

/// What a world's geoms look like: everything drawable, and why anything was drawn otherwise or
/// left out.
struct Scene {
  std::vector<GeomShape> geoms;
  std::vector<std::string> notes;  ///< e.g. "mesh \"base\" drawn as its bounding box"
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
  /// The names of the joints find_joint() accepts, in the model's order.
  virtual std::vector<std::string> joints() const = 0;
  /// The index of the body called `name`, or nullopt.
  virtual std::optional<std::size_t> find_body(std::string_view name) const = 0;
  /// The names of the bodies find_body() accepts, in the model's order.
  virtual std::vector<std::string> bodies() const = 0;
  /// The length of one step, s.
  virtual double timestep_s() const = 0;
  /// Adds rotor inertia seen at the joint (an actuator's gearbox), kg·m².
  virtual void add_armature(std::size_t joint, double kg_m2) = 0;
  /// The generalized force on `joint` for the following steps (N·m on a hinge), until set again.
  virtual void set_torque(std::size_t joint, double torque_nm) = 0;
  /// A generalized force on `joint` from outside (the control API), added to set_torque()'s for
  /// the following steps, until set again.
  virtual void set_external_torque(std::size_t joint, double torque_nm) = 0;
  /// A wrench on `body` for the following steps, until set again (zero: none).
  virtual void set_wrench(std::size_t body, const Wrench& wrench) = 0;
  /// The wrench set_wrench() last put on `body`.
  virtual Wrench wrench(std::size_t body) const = 0;
  /// Advances one timestep.
  virtual void step() = 0;
  /// The joint now.
  virtual JointState joint(std::size_t joint) const = 0;
  /// The forces on `joint` in the last step (zero before the first).
  virtual JointForces forces(std::size_t joint) const = 0;
  /// The geoms to draw (fixed for the world's life), and notes on those it could not draw as
  /// they are.
  virtual Scene scene() const = 0;
  /// The pose of each of scene()'s geoms in the current state, in scene()'s order. Not const:
  /// an engine may have to compute its kinematics for the state now.
  virtual std::vector<GeomPose> geom_poses() = 0;
};

}  // namespace dxlemu::physics
