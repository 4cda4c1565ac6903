#pragma once

#include "control/request.hpp"

// The control API's commands on the physics world: physics, physics.apply and
// physics.scene (docs/control-api.md, docs/physics.md).
namespace dxlemu::control {

/// physics {"joint"?}: the world caught up to now: its joints (position, velocity, the forces
/// on each, the servo driving it) and the wrenches applied to bodies; with "joint", that joint.
ordered_json physics_state(Target& target, const Args& args);

/// physics.apply {"joint", "torque_nm"} or {"body", "force_n"?, "torque_nm"?}: from now on pushes
/// the joint with a generalized force (added to its servo's), or the body with a force and a
/// torque at its centre of mass (world frame), until applied again; zero removes it. The result
/// is the joint's or body's state as `physics` reports it.
ordered_json physics_apply(Target& target, const Args& args);

/// physics.scene {}: the world's geoms for drawing, caught up to now: each one's name, body,
/// shape (type, size), colour and world pose, and notes on geoms drawn otherwise or left out.
ordered_json physics_scene(Target& target, const Args& args);

/// Refuses `args` of physics or physics.apply that name no joint or body of the world, or a
/// target without physics (Api::check, for scenarios).
void check_physics_request(Target& target, const Args& args);

}  // namespace dxlemu::control
