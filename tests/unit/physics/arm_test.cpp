// The shipped arms on MuJoCo (docs/physics.md "Shipped arms"): robots/openmanipulator-x.json and
// robots/so101-follower.json with their physics files (robots/physics/), merged as a config
// carrying both would be, every servo on its joint of one world, on the hand-advanced virtual
// clock. What the servos read is compared with what a separate MuJoCo run of the same MJCF says
// holding the arm still takes (test::holding_forces). Built only with MuJoCo.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "arm_rig.hpp"
#include "physics/physics_fixtures.hpp"

using namespace dxlemu;
using std::chrono::milliseconds;

namespace {

using test::kPulsesPerRad;

const std::string kRobots = DXLEMU_ROBOTS_DIR;
constexpr std::int64_t kCentre = 2048;  // Present Position at every joint's zero
// Long enough for every joint to reach its goal and settle (the slowest, damped, takes < 1 s).
constexpr milliseconds kSettle{3000};

/// One shipped arm: its profile, its physics file and the names of its items.
struct Arm {
  std::string profile;
  std::string torque_key;
  /// Joint name by servo ID, as the physics file maps them.
  std::map<std::uint8_t, std::string> joints;
};

const Arm kOpenManipulator{
    "openmanipulator-x",
    "torque_enable",
    {{11, "joint1"}, {12, "joint2"}, {13, "joint3"}, {14, "joint4"}, {15, "gripper_left_joint"}}};
const Arm kSo101{"so101-follower",
                 "torque_switch",
                 {{1, "shoulder_pan"},
                  {2, "shoulder_lift"},
                  {3, "elbow_flex"},
                  {4, "wrist_flex"},
                  {5, "wrist_roll"},
                  {6, "gripper"}}};

app::BusConfig arm_config(const Arm& arm) {
  return test::profile_with_physics(kRobots + "/" + arm.profile + ".json",
                                    kRobots + "/physics/" + arm.profile + ".json");
}

/// The rig of one arm with every servo's torque on, holding where it stands.
struct HeldArm {
  explicit HeldArm(const Arm& a) : arm(a), config(arm_config(a)), rig(config) {
    for (const auto& [id, joint] : arm.joints) {
      rig.set(id, "goal_position", rig.get(id, "present_position"));
      rig.set(id, arm.torque_key, 1);
    }
  }
  /// Goal Position of servo `id` for its joint at `rad` (a hinge of gear 1).
  void goal_rad(std::uint8_t id, double rad) {
    rig.set(id, "goal_position", kCentre + std::lround(rad * kPulsesPerRad));
  }
  /// Every joint's position now in the world, by name.
  std::map<std::string, double> pose() {
    std::map<std::string, double> q;
    physics::World& world = rig.clock()->world();
    for (const auto& [id, joint] : arm.joints) {
      q[joint] = world.joint(world.find_joint(joint).value()).position_rad;
    }
    return q;
  }
  /// What MuJoCo says servo `id` must give to hold the arm where it is now, in units of
  /// `load_key` (Present Current, or Present Load in 0.1 % of stall torque).
  double expected_units(std::uint8_t id, const std::string& load_key) {
    const auto forces = test::holding_forces(config.physics->mjcf, pose());
    const app::JointConfig& j = joint_config(id);
    const double shaft_nm = forces.at(j.joint) * j.direction / j.gear;
    const model::MotorParams& p = rig.servo(id).motion().params();
    if (load_key == "present_load") {
      constexpr double kLoadPerStall = 1000;
      return shaft_nm / p.stall_torque_nm * kLoadPerStall;
    }
    const double torque_constant = p.stall_torque_nm / p.stall_current_a;  // N·m per A
    return shaft_nm / torque_constant / p.current_unit_a.value();
  }
  const app::JointConfig& joint_config(std::uint8_t id) const {
    for (const app::JointConfig& j : config.physics->joints) {
      if (j.id == id) {
        return j;
      }
    }
    throw std::out_of_range("no joint for ID " + std::to_string(id));
  }
  /// Servo `id`'s friction allowance in its load units: MuJoCo's frictionloss of the joint can
  /// hold up to that much of the load itself, so the servo's share is known only to within it.
  double friction_units(std::uint8_t id, double frictionloss_nm) {
    const model::MotorParams& p = rig.servo(id).motion().params();
    return frictionloss_nm / (p.stall_torque_nm / p.stall_current_a) / p.current_unit_a.value();
  }

  Arm arm;
  app::BusConfig config;
  test::ArmRig rig;
};

// The frictionloss of the SO-101's joints (robots/physics/so101-follower.xml); the
// OpenMANIPULATOR-X's joints have none.
constexpr double kSo101FrictionNm = 0.052;
// What a servo reads beyond MuJoCo's figure: rounding to the unit, and the P controller's
// settling wobble, in units.
constexpr double kReadingUnits = 2;

}  // namespace

TEST_CASE("The OpenMANIPULATOR-X starts at its zero pose with every servo reading 2048",
          "[physics][mujoco]") {
  HeldArm a(kOpenManipulator);
  for (const auto& [id, joint] : a.arm.joints) {
    CAPTURE(joint);
    CHECK(a.rig.get(id, "present_position") == kCentre);
  }
}

TEST_CASE(
    "The OpenMANIPULATOR-X held at a pose draws on each joint the current its gravity "
    "torque predicts",
    "[physics][mujoco]") {
  HeldArm a(kOpenManipulator);
  a.goal_rad(12, 0.5);   // upper arm leaning forward
  a.goal_rad(13, -0.3);  // forearm a little above level
  a.goal_rad(14, 0.6);   // wrist down
  a.rig.wait(kSettle);
  CHECK(a.pose().at("joint2") == Approx(0.5).margin(0.02));
  for (const auto& [id, joint] : a.arm.joints) {
    CAPTURE(joint);
    const double expected = a.expected_units(id, "present_current");
    CAPTURE(expected);
    CHECK(std::abs(static_cast<double>(a.rig.get(id, "present_current")) - expected) <=
          kReadingUnits);
    CHECK(a.rig.get(id, "hardware_error_status") == 0);
  }
  // The pose loads the shoulder and the elbow well beyond the tolerance.
  CHECK(std::abs(a.expected_units(12, "present_current")) > 50);
  CHECK(std::abs(a.expected_units(13, "present_current")) > 50);
}

TEST_CASE(
    "The OpenMANIPULATOR-X shoulder's holding current follows the elbow folding and "
    "stretching the forearm",
    "[physics][mujoco]") {
  HeldArm a(kOpenManipulator);
  a.goal_rad(12, 0.3);
  a.rig.wait(kSettle);
  const double stretched = static_cast<double>(a.rig.get(12, "present_current"));
  const double stretched_expected = a.expected_units(12, "present_current");
  // Only the elbow moves: it folds the forearm up and back over the upper arm.
  a.goal_rad(13, -1.4);
  a.rig.wait(kSettle);
  CHECK(a.pose().at("joint3") == Approx(-1.4).margin(0.02));
  const double folded = static_cast<double>(a.rig.get(12, "present_current"));
  const double folded_expected = a.expected_units(12, "present_current");
  CAPTURE(stretched, stretched_expected, folded, folded_expected);
  // Its goal did not change, yet the shoulder holds a different load: the forearm's weight,
  // which only reaches it through the world.
  CHECK(std::abs(folded_expected - stretched_expected) > 5 * kReadingUnits);
  CHECK(folded - stretched ==
        Approx(folded_expected - stretched_expected).margin(2 * kReadingUnits));
  CHECK(a.rig.get(12, "goal_position") == kCentre + std::lround(0.3 * kPulsesPerRad));
}

TEST_CASE(
    "With the elbow's torque off the OpenMANIPULATOR-X forearm falls and the shoulder "
    "takes its new load",
    "[physics][mujoco]") {
  HeldArm a(kOpenManipulator);
  a.goal_rad(13, -1.0);
  a.rig.wait(kSettle);
  const double before = static_cast<double>(a.rig.get(12, "present_current"));
  REQUIRE(std::abs(before - a.expected_units(12, "present_current")) <= kReadingUnits);
  a.rig.set(13, "torque_enable", 0);
  a.rig.wait(kSettle);
  // The forearm hangs on its stop (joint3's upper limit, 1.4 rad); the elbow draws nothing.
  CHECK(a.pose().at("joint3") == Approx(1.4).margin(0.03));
  CHECK(a.rig.get(13, "present_current") == 0);
  CHECK(a.rig.get(13, "present_position") > kCentre + std::lround(1.35 * kPulsesPerRad));
  const double after = static_cast<double>(a.rig.get(12, "present_current"));
  const double after_expected = a.expected_units(12, "present_current");
  CAPTURE(before, after, after_expected);
  CHECK(std::abs(after - after_expected) <= kReadingUnits);
  // The change is many times the tolerance: a shoulder that did not feel the forearm fails.
  CHECK(std::abs(after - before) > 5 * kReadingUnits);
}

TEST_CASE("The OpenMANIPULATOR-X gripper servo drives both fingers through its gear",
          "[physics][mujoco]") {
  HeldArm a(kOpenManipulator);
  // 0.5 rad of servo past 2048: the fingers close by 0.5 * 0.015 m (direction -1).
  a.rig.set(15, "goal_position", kCentre + std::lround(0.5 * kPulsesPerRad));
  a.rig.wait(kSettle);
  const auto q = a.pose();
  CHECK(q.at("gripper_left_joint") == Approx(-0.0075).margin(0.0003));
  physics::World& world = a.rig.clock()->world();
  CHECK(world.joint(world.find_joint("gripper_right_joint").value()).position_rad ==
        Approx(-0.0075).margin(0.0005));
}

TEST_CASE(
    "The SO-101 follower held at a pose draws on each joint the current its gravity "
    "torque predicts",
    "[physics][mujoco]") {
  HeldArm a(kSo101);
  for (const auto& [id, joint] : a.arm.joints) {
    CAPTURE(joint);
    CHECK(a.rig.get(id, "present_position") == kCentre);
  }
  a.goal_rad(2, -0.4);
  a.goal_rad(3, 0.5);
  a.goal_rad(4, 0.3);
  a.rig.wait(kSettle);
  for (const auto& [id, joint] : a.arm.joints) {
    CAPTURE(joint);
    const double expected = a.expected_units(id, "present_current");
    CAPTURE(expected);
    CHECK(std::abs(static_cast<double>(a.rig.get(id, "present_current")) - expected) <=
          a.friction_units(id, kSo101FrictionNm) + kReadingUnits);
  }
  CHECK(std::abs(a.expected_units(2, "present_current")) >
        3 * a.friction_units(2, kSo101FrictionNm));
}

TEST_CASE("The SO-101 shoulder's holding current follows the elbow stretching the forearm",
          "[physics][mujoco]") {
  HeldArm a(kSo101);
  a.goal_rad(3, 1.5);
  a.rig.wait(kSettle);
  const double folded = static_cast<double>(a.rig.get(2, "present_current"));
  const double folded_expected = a.expected_units(2, "present_current");
  a.goal_rad(3, -0.5);
  a.rig.wait(kSettle);
  const double stretched = static_cast<double>(a.rig.get(2, "present_current"));
  const double stretched_expected = a.expected_units(2, "present_current");
  CAPTURE(folded, folded_expected, stretched, stretched_expected);
  const double friction = a.friction_units(2, kSo101FrictionNm);
  CHECK(std::abs(stretched_expected - folded_expected) > 4 * friction);
  CHECK(stretched - folded ==
        Approx(stretched_expected - folded_expected).margin(2 * (friction + kReadingUnits)));
}

TEST_CASE("The SO-101 arm run twice gives the same control table bytes", "[physics][mujoco]") {
  auto run = [] {
    HeldArm a(kSo101);
    std::vector<std::uint8_t> trace;
    const std::vector<std::vector<double>> poses{{0.5, -0.6, 0.8, 0.4, 1.0, 0.6},
                                                 {-0.4, 0.3, -0.2, -0.5, -1.0, 0.1}};
    for (const auto& pose : poses) {
      for (std::size_t i = 0; i < pose.size(); ++i) {
        a.goal_rad(static_cast<std::uint8_t>(i + 1), pose[i]);  // IDs 1 to 6
      }
      for (int i = 0; i < 60; ++i) {
        a.rig.wait(milliseconds(7));
        const auto bytes = a.rig.table_bytes();
        trace.insert(trace.end(), bytes.begin(), bytes.end());
      }
    }
    a.rig.set(3, "torque_switch", 0);
    for (int i = 0; i < 60; ++i) {
      a.rig.wait(milliseconds(5));
      const auto bytes = a.rig.table_bytes();
      trace.insert(trace.end(), bytes.begin(), bytes.end());
    }
    return trace;
  };
  const std::vector<std::uint8_t> first = run();
  const std::vector<std::uint8_t> second = run();
  REQUIRE(first.size() == second.size());
  CHECK(first == second);
}
