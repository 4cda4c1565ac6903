// The control API's physics commands (docs/control-api.md "physics") on the shipped pendulum
// (docs/examples/physics/pendulum.xml: 0.5 kg at 0.1 m from a hinge about +y, stops at ±60°,
// body "link") with one XM430-W350 on its joint, through a test target on a hand-stepped clock.
// Built only with MuJoCo.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "physics/mjcf_world.hpp"
#include "physics/physics_fixtures.hpp"
#include "ports_target.hpp"

using namespace dxlemu;
using nlohmann::json;
using std::chrono::milliseconds;

namespace {

using test::kLevel;
using test::kPendulum;
using test::kPulsesPerRad;

constexpr double kStopRad = 60 * std::numbers::pi / 180;
// Gravity's torque on the link at angle q is m*g*l*cos(q), towards positive angles.
constexpr double kMgl = 0.5 * 9.81 * 0.1;

struct Rig : test::ApiRequests<Rig> {
  // Outlives the servo coupled to it.
  std::unique_ptr<physics::WorldClock> clock = std::make_unique<physics::WorldClock>(
      physics::load_mjcf_world(kPendulum, 0.001), milliseconds(1));
  test::PortsTarget target;
  test::PortsTarget::Port& arm = target.add_port("arm");
  model::Servo& servo = target.add(arm, "xm430-w350", 1);
  control::PhysicsView view{*clock, kPendulum, {{"shoulder", "arm", 1}}};
  control::Api api{target};

  Rig() {
    model::JointMapping mapping;
    mapping.joint = clock->world().find_joint("shoulder").value();
    mapping.zero_offset_rad = std::numbers::pi;
    servo.motion().couple(*clock, mapping);
    target.world = &view;
  }

  void wait_ms(int ms) { result(R"({"cmd":"clock.step","ms":)" + std::to_string(ms) + "}"); }
  std::int64_t present_position() {
    servo.advance_to(target.now());
    return servo.table().get(servo.table().index("present_position"));
  }
};

}  // namespace

TEST_CASE("physics reports the world, each joint with the servo on it and the forces on it",
          "[physics][mujoco][control]") {
  Rig rig;
  // Torque off: the link falls onto its +60° stop and rests there.
  rig.wait_ms(1000);
  const json state = rig.result(R"({"cmd":"physics"})");
  CHECK(state["engine"] == physics::physics_engine());
  CHECK(state["mjcf"] == kPendulum);
  CHECK(state["timestep_ms"].get<double>() == Approx(1));
  CHECK(state["time_ms"].get<double>() == Approx(1000));
  CHECK(state["bodies"] == json::array());
  REQUIRE(state["joints"].size() == 1);
  const json& joint = state["joints"][0];
  CHECK(joint["joint"] == "shoulder");
  CHECK(joint["port"] == "arm");
  CHECK(joint["servo"] == 1);
  CHECK(joint["position_rad"].get<double>() == Approx(kStopRad).margin(0.02));
  CHECK(std::abs(joint["velocity_rad_s"].get<double>()) < 0.01);
  CHECK(joint["servo_torque_nm"].get<double>() == 0);  // the winding is open
  CHECK(joint["external_torque_nm"].get<double>() == 0);
  // At rest on the stop, the stop carries gravity's torque: qfrc_bias = qfrc_constraint.
  const double gravity = kMgl * std::cos(kStopRad);
  CHECK(joint["bias_torque_nm"].get<double>() == Approx(-gravity).margin(0.005));
  CHECK(joint["constraint_torque_nm"].get<double>() == Approx(-gravity).margin(0.005));
  // The servo's shaft is where the joint is.
  CHECK(std::abs(static_cast<double>(rig.present_position() - kLevel) -
                 joint["position_rad"].get<double>() * kPulsesPerRad) <= 1);
  CHECK(rig.result(R"({"cmd":"physics","joint":"shoulder"})") == joint);
}

TEST_CASE("physics.apply pushes a joint from now on, and 0 removes the push",
          "[physics][mujoco][control]") {
  Rig rig;
  rig.wait_ms(1000);  // on the +60° stop
  // More than gravity's m*g*l at any angle, the other way: the link swings up onto -60°.
  const json pushed = rig.result(R"({"cmd":"physics.apply","joint":"shoulder","torque_nm":-1})");
  CHECK(pushed["external_torque_nm"] == -1.0);
  CHECK(pushed["position_rad"].get<double>() == Approx(kStopRad).margin(0.02));  // not yet moved
  rig.wait_ms(1000);
  const json up = rig.result(R"({"cmd":"physics","joint":"shoulder"})");
  CHECK(up["position_rad"].get<double>() == Approx(-kStopRad).margin(0.02));
  CHECK(up["external_torque_nm"] == -1.0);
  CHECK(std::abs(rig.present_position() - (kLevel - std::lround(kStopRad * kPulsesPerRad))) <= 10);
  rig.result(R"({"cmd":"physics.apply","joint":"shoulder","torque_nm":0})");
  rig.wait_ms(1000);
  CHECK(rig.result(R"({"cmd":"physics","joint":"shoulder"})")["position_rad"].get<double>() ==
        Approx(kStopRad).margin(0.02));
}

TEST_CASE("physics.apply pushes a body with a force at its centre of mass",
          "[physics][mujoco][control]") {
  Rig rig;
  rig.wait_ms(1000);  // on the +60° stop
  // 10 N up at the link's centre of mass (0.1 m out along x at level) turns it up, about -y.
  const json body = rig.result(R"({"cmd":"physics.apply","body":"link","force_n":[0,0,10]})");
  CHECK(body ==
        json::parse(R"({"body":"link","force_n":[0.0,0.0,10.0],"torque_nm":[0.0,0.0,0.0]})"));
  rig.wait_ms(1000);
  const json state = rig.result(R"({"cmd":"physics"})");
  CHECK(state["bodies"] == json::array({body}));
  CHECK(state["joints"][0]["position_rad"].get<double>() == Approx(-kStopRad).margin(0.02));
  CHECK(state["joints"][0]["external_torque_nm"] == 0.0);  // a body's push is not the joint's
  rig.result(R"({"cmd":"physics.apply","body":"link","force_n":[0,0,0]})");
  CHECK(rig.result(R"({"cmd":"physics"})")["bodies"] == json::array());
}

TEST_CASE("physics and physics.apply refuse what the world does not have",
          "[physics][mujoco][control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"physics","joint":"elbow"})") ==
        "the world has no hinge or slide joint \"elbow\" (its joints: shoulder)");
  CHECK(rig.error(R"({"cmd":"physics.apply","body":"arm","force_n":[0,0,1]})") ==
        "the world has no body \"arm\" (its bodies: world, link)");
  const std::string one_of =
      "physics.apply takes one of \"joint\" (with \"torque_nm\") or \"body\" (with \"force_n\" "
      "and/or \"torque_nm\")";
  CHECK(rig.error(R"({"cmd":"physics.apply"})") == one_of);
  CHECK(rig.error(R"({"cmd":"physics.apply","joint":"shoulder","body":"link"})") == one_of);
  CHECK(rig.error(R"({"cmd":"physics.apply","joint":"shoulder"})") ==
        "\"torque_nm\" is required: the generalized force on the joint (N·m, or N on a slide); 0 "
        "removes it");
  CHECK(rig.error(R"({"cmd":"physics.apply","joint":"shoulder","force_n":[1,0,0]})") ==
        "\"force_n\" is for a body: a joint takes \"torque_nm\" (N·m, or N on a slide)");
  CHECK(rig.error(R"({"cmd":"physics.apply","body":"link"})") ==
        "a body takes \"force_n\" and/or \"torque_nm\" ([x, y, z]); zeros remove them");
  CHECK(rig.error(R"({"cmd":"physics.apply","body":"link","force_n":[1,2]})") ==
        "\"force_n\" of a body must be [x, y, z] in world coordinates");
  CHECK(rig.error(R"({"cmd":"physics.apply","body":"link","torque_nm":[1,"2",3]})") ==
        "\"torque_nm\" must hold three numbers");
  CHECK(rig.error(R"({"cmd":"physics.apply","body":"link","torque_nm":2})") ==
        "\"torque_nm\" of a body must be [x, y, z] in world coordinates");
  // A scenario's step naming a joint the world lacks is refused before it is scheduled.
  CHECK(control::Api::check(rig.target, json::parse(R"({"cmd":"physics","joint":"elbow"})")) ==
        "the world has no hinge or slide joint \"elbow\" (its joints: shoulder)");
  // Nothing refused was applied.
  CHECK(rig.result(R"({"cmd":"physics"})")["bodies"] == json::array());
}

TEST_CASE("A scenario step pushes the world at its time", "[physics][mujoco][control]") {
  Rig rig;
  CHECK(
      rig.result(R"({"cmd":"scenario.load","scenario":{"steps":[)"
                 R"({"at_ms":1000,"cmd":"physics.apply","joint":"shoulder","torque_nm":-1}]}})") ==
      json::parse(R"({"steps":1,"scenario":1})"));
  rig.wait_ms(999);
  CHECK(rig.result(R"({"cmd":"physics","joint":"shoulder"})")["external_torque_nm"] == 0.0);
  rig.wait_ms(1001);
  const json joint = rig.result(R"({"cmd":"physics","joint":"shoulder"})");
  CHECK(joint["external_torque_nm"] == -1.0);
  CHECK(joint["position_rad"].get<double>() == Approx(-kStopRad).margin(0.02));
  // A step naming a joint the world lacks refuses the whole scenario.
  CHECK(rig.error(R"({"cmd":"scenario.load","scenario":{"steps":[)"
                  R"({"at_ms":0,"cmd":"physics.apply","joint":"elbow","torque_nm":1}]}})") ==
        "scenario/steps/0: the world has no hinge or slide joint \"elbow\" (its joints: shoulder)");
}

TEST_CASE("physics.scene gives each geom's shape and its pose now", "[physics][mujoco][control]") {
  Rig rig;
  const json level = rig.result(R"({"cmd":"physics.scene"})");
  CHECK(level["notes"] == json::array());
  REQUIRE(level["geoms"].size() == 2);
  const json& rod = level["geoms"][0];
  CHECK(rod["name"] == "");
  CHECK(rod["body"] == "link");
  CHECK(rod["type"] == "capsule");
  CHECK(rod["size"][0].get<double>() == Approx(0.005));
  CHECK(rod["size"][1].get<double>() == Approx(0.05));
  CHECK(rod["rgba"] == json::parse("[0.5, 0.5, 0.5, 1.0]"));
  CHECK(rod["pos"][0].get<double>() == Approx(0.05));
  CHECK(rod["mat"].size() == 9);
  CHECK(level["geoms"][1]["type"] == "sphere");
  CHECK(level["geoms"][1]["pos"][0].get<double>() == Approx(0.1));
  // Torque off, the link falls onto its +60° stop: the mass turns down towards -z.
  rig.wait_ms(1000);
  const json fallen = rig.result(R"({"cmd":"physics.scene"})");
  const json& mass = fallen["geoms"][1]["pos"];
  CHECK(mass[0].get<double>() == Approx(0.1 * std::cos(kStopRad)).margin(0.002));
  CHECK(mass[1].get<double>() == Approx(0).margin(1e-9));
  CHECK(mass[2].get<double>() == Approx(-0.1 * std::sin(kStopRad)).margin(0.002));
  // Exactly where the joint is now.
  const double q = rig.result(R"({"cmd":"physics","joint":"shoulder"})")["position_rad"];
  CHECK(mass[0].get<double>() == Approx(0.1 * std::cos(q)).epsilon(1e-9));
  CHECK(mass[2].get<double>() == Approx(-0.1 * std::sin(q)).epsilon(1e-9));
  CHECK(rig.error(R"({"cmd":"physics.scene","joint":"shoulder"})") ==
        "unknown field \"joint\" for physics.scene (it takes no arguments)");
}
