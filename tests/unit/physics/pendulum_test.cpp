// Servos carrying real loads through MuJoCo (docs/physics.md), on the shipped one-link pendulum
// (docs/examples/physics/pendulum.xml: 0.5 kg at 0.1 m, hinge stops at ±60°) and one XM430-W350
// coupled to it with the shipped config's mapping (Present Position 2048 with the link level).
// Everything runs on the hand-advanced virtual clock; values are read from the control table.
// Built only with MuJoCo.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "model/servo.hpp"
#include "physics/mjcf_world.hpp"
#include "physics/physics_fixtures.hpp"
#include "physics/world_clock.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using std::chrono::milliseconds;

namespace {

using test::kLevel;
using test::kPendulum;

// The pendulum as its MJCF states it.
constexpr double kMassKg = 0.5;
constexpr double kArmM = 0.1;
constexpr double kGravity = 9.81;
constexpr double kLinkInertia = kMassKg * kArmM * kArmM + 1e-6;  // point mass plus diaginertia
constexpr double kLimitRad = 60 * std::numbers::pi / 180;

// XM430-W350 figures (models/xm430-w350.json): units of Present Current and Present Velocity.
constexpr double kCurrentUnitA = 0.00269;
constexpr double kVelocityUnitRadS = 0.229 * 2 * std::numbers::pi / 60;
constexpr double kPulsesPerRev = 4096;
constexpr std::int64_t kHwOverload = 0x20;  // Hardware Error Status: Overload Error

/// The pendulum world and one XM430-W350 on its shoulder, stepped on a virtual clock.
struct Pendulum {
  explicit Pendulum(const std::string& model = "xm430-w350")
      : clock(std::make_unique<physics::WorldClock>(physics::load_mjcf_world(kPendulum, 0.001),
                                                    milliseconds(1))),
        servo(test::shipped_model(model), 1) {
    model::JointMapping mapping;
    mapping.joint = clock->world().find_joint("shoulder").value();
    mapping.zero_offset_rad = std::numbers::pi;
    servo.motion().couple(*clock, mapping);
  }

  std::unique_ptr<physics::WorldClock> clock;  // outlives the servo coupled to it
  model::Servo servo;
  sim::SimTime now{};

  void wait_ms(int ms) {
    now += milliseconds(ms);
    servo.advance_to(now);
  }
  std::int64_t get(const std::string& key) const {
    return servo.table().get(servo.table().index(key));
  }
  void set(const std::string& key, std::int64_t value) {
    servo.advance_to(now);
    servo.device_write(servo.table().index(key), value);
  }
  /// The joint angle the servo reports, rad (0: level, positive: down).
  double angle() const {
    return static_cast<double>(get("present_position") - kLevel) * 2 * std::numbers::pi /
           kPulsesPerRev;
  }
  /// The motor's rotor inertia that the coupling adds to the joint (docs/physics.md).
  double armature() const {
    const model::MotorParams& p = servo.motion().params();
    return p.inertia * p.pulses_per_rev / (2 * std::numbers::pi) / 1e6;
  }
};

}  // namespace

TEST_CASE("Holding the link level draws the current m*g*l over the torque constant predicts",
          "[physics][mujoco]") {
  Pendulum p;
  REQUIRE(p.get("present_position") == kLevel);
  p.set("torque_enable", 1);
  p.wait_ms(2000);
  // Gravity pulls the link down (positive) with m*g*l; the motor holds it with as much the other
  // way, a little below the goal (a P controller's steady error).
  const double torque_constant = 4.1 / 2.3;  // stall torque over stall current
  const double expected = -kMassKg * kGravity * kArmM / torque_constant / kCurrentUnitA;  // -102.3
  CHECK(std::abs(static_cast<double>(p.get("present_current")) - expected) <= 2);  // 2 % or less
  CHECK(p.get("present_velocity") == 0);
  CHECK(p.get("present_position") > kLevel);
  CHECK(p.get("present_position") < kLevel + 16);
  CHECK(p.get("hardware_error_status") == 0);
  // The winding warms with the holding current (I²R), slowly.
  p.wait_ms(60'000);
  CHECK(p.get("present_temperature") > 25);
}

TEST_CASE("A goal written again and again keeps the current that holds the link",
          "[physics][mujoco]") {
  // A teleoperation loop writes every joint's goal each period, mostly the same value. Without
  // a profile (Profile Velocity 0) the goal is the desired position at once: the position error
  // the P controller holds the load with must survive each write, not be planned away from the
  // shaft and built up again while gravity pulls.
  Pendulum p;
  p.set("torque_enable", 1);
  p.wait_ms(2000);
  const std::int64_t holding = p.get("present_current");
  const std::int64_t held = p.get("present_position");
  REQUIRE(holding < -90);
  for (int write = 0; write < 100; ++write) {
    p.set("goal_position", kLevel);
    p.wait_ms(1);
    INFO("write " << write);
    CHECK(std::abs(p.get("present_current") - holding) <= 2);
    p.wait_ms(9);
    CHECK(std::abs(p.get("present_position") - held) <= 1);
  }
}

TEST_CASE("With torque off the link falls as MuJoCo says", "[physics][mujoco]") {
  Pendulum p;
  p.wait_ms(150);
  // Energy: what the fall released is the kinetic energy of the link and the rotor.
  const double inertia = kLinkInertia + p.armature();
  const double q = p.angle();
  const double w = static_cast<double>(p.get("present_velocity")) * kVelocityUnitRadS;
  REQUIRE(q > 0.1);
  const double released = kMassKg * kGravity * kArmM * std::sin(q);
  const double kinetic = 0.5 * inertia * w * w;
  CHECK(kinetic == Approx(released).epsilon(0.03));
  CHECK(p.get("present_current") == 0);

  // The same fall in MuJoCo alone, no servo: the same angle, to the pulse.
  auto world = physics::load_mjcf_world(kPendulum, 0.001);
  const std::size_t joint = world->find_joint("shoulder").value();
  world->add_armature(joint, p.armature());
  for (int i = 0; i < 150; ++i) {
    world->step();
  }
  const double alone = world->joint(joint).position_rad;
  CHECK(p.get("present_position") ==
        kLevel + std::llround(alone * kPulsesPerRev / (2 * std::numbers::pi)));
  // And it comes to rest against its stop.
  p.wait_ms(5000);
  CHECK(p.angle() == Approx(kLimitRad).margin(0.02));
}

TEST_CASE("Pushing into a joint stop raises the current to its limit and trips Overload",
          "[physics][mujoco]") {
  Pendulum p;
  p.set("torque_enable", 1);
  // 90° down, 30° past the stop at 60°.
  p.set("goal_position", kLevel + 1024);
  const double stall_units = 2.3 / kCurrentUnitA;  // 855: all the motor gives at 12 V
  int at_limit_ms = -1;
  for (int t = 0; t < 1000 && at_limit_ms < 0; ++t) {
    p.wait_ms(1);
    if (static_cast<double>(p.get("present_current")) >= 0.95 * stall_units) {
      at_limit_ms = t + 1;
    }
  }
  REQUIRE(at_limit_ms > 0);
  CHECK(p.angle() == Approx(kLimitRad).margin(0.02));
  CHECK(static_cast<double>(p.get("present_current")) <= stall_units + 1);
  // docs/motion.md: a motor at its limit for overload_ms (1 s) raises Overload Error.
  const double overload_ms = p.servo.motion().params().overload_ms;
  p.wait_ms(static_cast<int>(overload_ms) - 20);
  CHECK(p.get("hardware_error_status") == 0);
  CHECK(p.get("torque_enable") == 1);
  p.wait_ms(40);
  CHECK(p.get("hardware_error_status") == kHwOverload);
  // Shutdown: torque off, no current; gravity keeps the link on its stop.
  CHECK(p.get("torque_enable") == 0);
  p.wait_ms(10);
  CHECK(p.get("present_current") == 0);
  CHECK(p.angle() == Approx(kLimitRad).margin(0.02));
}

TEST_CASE("Pushing into a joint stop raises Present Load to the motor's limit on an MX-28(2.0)",
          "[physics][mujoco]") {
  // MX-28(2.0) has no current sensor: its load reading is Present Load, 0.1 % of stall torque.
  Pendulum p("mx-28-2");
  REQUIRE(p.get("present_position") == kLevel);
  p.set("torque_enable", 1);
  p.wait_ms(1000);
  // Held level: m*g*l over its 2.5 N·m stall torque, -196 in 0.1 % (the sign: against gravity).
  const double holding = -kMassKg * kGravity * kArmM / 2.5 * 1000;
  CHECK(std::abs(static_cast<double>(p.get("present_load")) - holding) <= 4);
  p.set("goal_position", kLevel + 1024);
  p.wait_ms(500);
  CHECK(p.angle() == Approx(kLimitRad).margin(0.02));
  // All the motor gives at standstill: stall torque at the supply, 12.7 V at power-on over the
  // rated 12 V (docs/motion.md "Parameters"), so above the 1000 of the rated stall torque.
  const double full = 1000 * p.servo.motion().conditions().supply_v / 12;
  CHECK(std::abs(static_cast<double>(p.get("present_load")) - full) <= 2);
  CHECK(p.get("present_load") > 1000);
}

TEST_CASE("The same physics run twice gives the same control table bytes", "[physics][mujoco]") {
  auto run = [] {
    Pendulum p;
    std::vector<std::uint8_t> trace;
    auto record = [&] {
      const auto bytes = p.servo.table().bytes();
      trace.insert(trace.end(), bytes.begin(), bytes.end());
    };
    p.set("torque_enable", 1);
    p.set("profile_velocity", 50);
    p.set("goal_position", kLevel - 400);
    for (int i = 0; i < 100; ++i) {
      p.wait_ms(7);
      record();
    }
    p.set("torque_enable", 0);
    for (int i = 0; i < 100; ++i) {
      p.wait_ms(3);
      record();
    }
    return trace;
  };
  const std::vector<std::uint8_t> first = run();
  const std::vector<std::uint8_t> second = run();
  CHECK(first == second);
}

TEST_CASE("Two servos on one world step it once per tick, whichever is caught up",
          "[physics][mujoco]") {
  // Two pendulums side by side in one MJCF (tests/data/physics/two_pendulums.xml).
  auto clock = std::make_unique<physics::WorldClock>(
      physics::load_mjcf_world(std::string(DXLEMU_TEST_DATA_DIR) + "/physics/two_pendulums.xml",
                               0.0005),
      milliseconds(1));
  REQUIRE(clock->substeps() == 2);
  model::Servo holding(test::shipped_model("xm430-w350"), 1);
  model::Servo falling(test::shipped_model("xm430-w350"), 2);
  model::JointMapping left;
  left.joint = clock->world().find_joint("left").value();
  left.zero_offset_rad = std::numbers::pi;
  model::JointMapping right = left;
  right.joint = clock->world().find_joint("right").value();
  holding.motion().couple(*clock, left);
  falling.motion().couple(*clock, right);
  holding.device_write(holding.table().index("torque_enable"), 1);
  // Only the first servo is caught up: the world, and the second servo with it, move too.
  holding.advance_to(sim::SimTime{} + milliseconds(300));
  CHECK(clock->ticks() == 300);
  const auto position = [](const model::Servo& s) {
    return s.table().get(s.table().index("present_position"));
  };
  CHECK(position(holding) < kLevel + 16);
  CHECK(position(falling) > kLevel + 100);
  // Catching the second up to the same time runs no tick again.
  const std::int64_t fallen = position(falling);
  falling.advance_to(sim::SimTime{} + milliseconds(300));
  CHECK(clock->ticks() == 300);
  CHECK(position(falling) == fallen);
}

namespace dxlemu::test::pendulum_hand {

/// A hand that holds the shaft still at `position` pulses, pushing with up to `force_nm`.
class StillHand : public model::Hand {
 public:
  StillHand(double position, double force_nm) : grip_{position, 0, force_nm} {}
  std::optional<model::Grip> grip(sim::SimTime /*t*/) const override { return grip_; }
  bool still_from(sim::SimTime /*t*/) const override { return true; }

 private:
  model::Grip grip_;
};

}  // namespace dxlemu::test::pendulum_hand

TEST_CASE("A hand holds a torque-off link up against gravity, as far as its force goes",
          "[physics][mujoco][hand]") {
  // 30° above level: gravity pulls with m·g·l·cos 30° = 0.42 N·m; the hand's spring is as stiff
  // as the servo's own position loop (4.1 N·m over 64 pulses), so it sags about 7 pulses.
  const double up = kLevel - kPulsesPerRev / 12;
  Pendulum strong;
  strong.servo.motion().set_hand(std::make_shared<dxlemu::test::pendulum_hand::StillHand>(up, 2.0));
  strong.wait_ms(2000);
  CHECK(std::abs(static_cast<double>(strong.get("present_position")) - up) <= 10);
  CHECK(strong.get("present_current") == 0);  // the servo itself gives nothing
  // A hand weaker than gravity at the stop (0.25 N·m there) lets the link fall onto it.
  Pendulum weak;
  weak.servo.motion().set_hand(std::make_shared<dxlemu::test::pendulum_hand::StillHand>(up, 0.2));
  weak.wait_ms(3000);
  CHECK(weak.angle() == Approx(kLimitRad).margin(0.02));
}
