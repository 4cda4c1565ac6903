#include "control/physics_commands.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "physics/mjcf_world.hpp"

namespace dxlemu::control {
namespace {

constexpr double kMsPerS = 1e3;

PhysicsView& view_of(Target& target) {
  PhysicsView* view = target.physics();
  if (view == nullptr) {
    refuse("this daemon simulates no physics: its config has no \"physics\" (docs/physics.md)");
  }
  return *view;
}

std::string names_of(const std::vector<std::string>& names) {
  return names.empty() ? "none" : joined(names);
}

std::size_t joint_of(const PhysicsView& view, const std::string& name) {
  const physics::World& world = view.clock.world();
  const auto found = world.find_joint(name);
  if (!found) {
    refuse("the world has no hinge or slide joint " + json_quoted(name) +
           " (its joints: " + names_of(world.joints()) + ")");
  }
  return *found;
}

std::size_t body_of(const PhysicsView& view, const std::string& name) {
  const physics::World& world = view.clock.world();
  const auto found = world.find_body(name);
  if (!found) {
    refuse("the world has no body " + json_quoted(name) +
           " (its bodies: " + names_of(world.bodies()) + ")");
  }
  return *found;
}

ordered_json vector_json(const std::array<double, 3>& v) {
  return ordered_json::array({v[0], v[1], v[2]});
}

ordered_json joint_json(const PhysicsView& view, const std::string& name) {
  const physics::World& world = view.clock.world();
  const std::size_t index = joint_of(view, name);
  const physics::JointState state = world.joint(index);
  const physics::JointForces forces = world.forces(index);
  ordered_json out = {{"joint", name}};
  for (const CoupledJoint& coupled : view.coupled) {
    if (coupled.joint == name) {
      out["port"] = coupled.port;
      out["servo"] = coupled.servo;
    }
  }
  out["position_rad"] = state.position_rad;
  out["velocity_rad_s"] = state.velocity_rad_s;
  out["servo_torque_nm"] = forces.actuator;
  out["external_torque_nm"] = forces.external;
  out["constraint_torque_nm"] = forces.constraint;
  out["bias_torque_nm"] = forces.bias;
  return out;
}

ordered_json body_json(const PhysicsView& view, const std::string& name) {
  const physics::Wrench w = view.clock.world().wrench(body_of(view, name));
  return {{"body", name}, {"force_n", vector_json(w.force)}, {"torque_nm", vector_json(w.torque)}};
}

bool is_zero(const physics::Wrench& w) {
  for (std::size_t i = 0; i < 3; ++i) {
    if (w.force[i] != 0 || w.torque[i] != 0) {
      return false;
    }
  }
  return true;
}

// "force_n" or "torque_nm" of a body: three finite numbers, x y z in world coordinates.
std::array<double, 3> vector_arg(const Args& args, const char* key) {
  std::array<double, 3> out{};
  const ordered_json* value = args.value(key);
  if (value == nullptr) {
    return out;
  }
  if (!value->is_array() || value->size() != 3) {
    refuse(json_quoted(key) + " of a body must be [x, y, z] in world coordinates");
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const ordered_json& c = (*value)[i];
    if (!c.is_number() || !std::isfinite(c.get<double>())) {
      refuse(json_quoted(key) + " must hold three numbers");
    }
    out[i] = c.get<double>();
  }
  return out;
}

std::string_view type_name(physics::GeomType type) {
  switch (type) {
    case physics::GeomType::Plane:
      return "plane";
    case physics::GeomType::Sphere:
      return "sphere";
    case physics::GeomType::Capsule:
      return "capsule";
    case physics::GeomType::Ellipsoid:
      return "ellipsoid";
    case physics::GeomType::Cylinder:
      return "cylinder";
    case physics::GeomType::Box:
      return "box";
    case physics::GeomType::Mesh:
      return "mesh";
  }
  return "box";
}

template <std::size_t N>
ordered_json numbers_json(const std::array<double, N>& values) {
  ordered_json out = ordered_json::array();
  for (const double v : values) {
    out.push_back(v);
  }
  return out;
}

// Which of "joint" and "body" a physics.apply names, refusing neither or both.
void check_target_of_apply(const Args& args) {
  if (args.has("joint") == args.has("body")) {
    refuse(
        "physics.apply takes one of \"joint\" (with \"torque_nm\") or \"body\" (with "
        "\"force_n\" and/or \"torque_nm\")");
  }
  if (args.has("joint") && args.has("force_n")) {
    refuse("\"force_n\" is for a body: a joint takes \"torque_nm\" (N·m, or N on a slide)");
  }
}

}  // namespace

void check_physics_request(Target& target, const Args& args) {
  const PhysicsView& view = view_of(target);
  if (args.command() == "physics.apply") {
    check_target_of_apply(args);
  }
  if (const auto joint = args.string("joint")) {
    joint_of(view, *joint);
  }
  if (const auto body = args.string("body")) {
    body_of(view, *body);
  }
}

ordered_json physics_state(Target& target, const Args& args) {
  PhysicsView& view = view_of(target);
  view.clock.advance_to(target.now());
  if (const auto joint = args.string("joint")) {
    return joint_json(view, *joint);
  }
  const physics::World& world = view.clock.world();
  ordered_json joints = ordered_json::array();
  for (const std::string& name : world.joints()) {
    joints.push_back(joint_json(view, name));
  }
  ordered_json bodies = ordered_json::array();
  for (const std::string& name : world.bodies()) {
    if (!is_zero(world.wrench(body_of(view, name)))) {
      bodies.push_back(body_json(view, name));
    }
  }
  const double tick_ms = std::chrono::duration<double, std::milli>(view.clock.tick()).count();
  return {{"engine", physics::physics_engine()},
          {"mjcf", view.mjcf.string()},
          {"timestep_ms", world.timestep_s() * kMsPerS},
          {"time_ms", static_cast<double>(view.clock.ticks()) * tick_ms},
          {"joints", joints},
          {"bodies", bodies}};
}

ordered_json physics_scene(Target& target, const Args& /*args*/) {
  PhysicsView& view = view_of(target);
  view.clock.advance_to(target.now());
  physics::World& world = view.clock.world();
  const physics::Scene scene = world.scene();
  const std::vector<physics::GeomPose> poses = world.geom_poses();
  ordered_json geoms = ordered_json::array();
  for (std::size_t i = 0; i < scene.geoms.size() && i < poses.size(); ++i) {
    const physics::GeomShape& shape = scene.geoms[i];
    geoms.push_back({{"name", shape.name},
                     {"body", shape.body},
                     {"type", type_name(shape.type)},
                     {"size", numbers_json(shape.size)},
                     {"rgba", numbers_json(shape.rgba)},
                     {"pos", numbers_json(poses[i].pos)},
                     {"mat", numbers_json(poses[i].mat)}});
    if (shape.type == physics::GeomType::Mesh) {
      geoms.back()["mesh"] = shape.mesh;
    }
  }
  return {{"geoms", std::move(geoms)}, {"notes", scene.notes}};
}

ordered_json physics_apply(Target& target, const Args& args) {
  PhysicsView& view = view_of(target);
  check_target_of_apply(args);
  // Everything before now happened without the push.
  view.clock.advance_to(target.now());
  physics::World& world = view.clock.world();
  if (const auto joint = args.string("joint")) {
    const std::size_t index = joint_of(view, *joint);
    const auto torque = args.number("torque_nm");
    if (!torque || !std::isfinite(*torque)) {
      refuse(
          "\"torque_nm\" is required: the generalized force on the joint (N·m, or N on a "
          "slide); 0 removes it");
    }
    world.set_external_torque(index, *torque);
    return joint_json(view, *joint);
  }
  const std::string body = *args.string("body");
  const std::size_t index = body_of(view, body);
  if (!args.has("force_n") && !args.has("torque_nm")) {
    refuse("a body takes \"force_n\" and/or \"torque_nm\" ([x, y, z]); zeros remove them");
  }
  world.set_wrench(index, {vector_arg(args, "force_n"), vector_arg(args, "torque_nm")});
  return body_json(view, body);
}

}  // namespace dxlemu::control
