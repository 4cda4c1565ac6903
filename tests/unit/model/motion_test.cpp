// The motion model on the virtual clock (model/motion/motion_model.hpp, docs/motion.md): profiles
// against the e-Manual formulas, operating modes, mode-change resets, the motor under load and
// blocked, heat, hardware errors with Shutdown and Reboot, Protocol 1.0 wheel mode and Alarm
// Shutdown, and determinism.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <string>

#include "bus_write.hpp"
#include "model/servo.hpp"
#include "shipped_model.hpp"
#include "status_bytes.hpp"

using namespace dxlemu;
using model::Servo;
using std::chrono::milliseconds;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

using test::kAlert;
using test::kDataRange;
using test::kInPosition;
using test::kResultFail;

// Status error bytes (protocol2.md "Error"; protocol1.md "Error").
constexpr std::uint8_t kOk = 0x00;
constexpr std::uint8_t kV1Overheating = 0x04;
constexpr std::uint8_t kV1Overload = 0x20;

// X Operating Mode, Drive Mode and Moving Status values.
constexpr std::int64_t kVelocityMode = 1;
constexpr std::int64_t kPositionMode = 3;
constexpr std::int64_t kExtendedMode = 4;
constexpr std::int64_t kCurrentPositionMode = 5;
constexpr std::int64_t kTimeBased = 0x04;
constexpr std::int64_t kProfileOngoing = 0x02;
constexpr std::int64_t kFollowingError = 0x08;
constexpr std::int64_t kTrapezoidal = 0x30;
constexpr std::int64_t kTriangular = 0x20;

// X Hardware Error Status bits.
constexpr std::int64_t kHwVoltage = 0x01;
constexpr std::int64_t kHwOverheating = 0x04;
constexpr std::int64_t kHwOverload = 0x20;

constexpr double kXPulsesPerRev = 4096;
constexpr std::int64_t kTurn = 4096;  // X pulses per revolution

/// One servo on a hand-advanced simulated clock, driven by bus instructions.
struct Rig {
  explicit Rig(const std::string& model, std::uint8_t id = 1)
      : servo(test::shipped_model(model), id) {}

  Servo servo;
  sim::SimTime now{};

  /// Lets `ms` of simulated time pass.
  void wait(double ms) {
    now +=
        std::chrono::duration_cast<sim::SimDuration>(std::chrono::duration<double, std::milli>(ms));
    servo.advance_to(now);
  }
  /// Moves the clock to `ms` after power-on.
  void at(double ms) {
    const sim::SimTime t{std::chrono::duration_cast<sim::SimDuration>(
        std::chrono::duration<double, std::milli>(ms))};
    REQUIRE(t >= now);
    now = t;
    servo.advance_to(now);
  }
  /// A Write instruction of `key` = `value` in the servo's protocol, as the bus delivers it;
  /// returns the status error byte.
  std::uint8_t write(const std::string& key, std::int64_t value) {
    servo.advance_to(now);
    return test::bus_write(servo, key, value);
  }
  /// The error byte of a Ping status now (carries the alert bit and 1.0 hardware error bits).
  std::uint8_t ping_error() {
    servo.advance_to(now);
    return servo
        .execute({servo.protocol().value_or(Protocol::V2), servo.id(), wire::Ping{}},
                 model::Addressing::Unicast)
        .error;
  }
  std::int64_t get(const std::string& key) const { return servo.table().get(key); }
  void conditions(const std::function<void(model::Conditions&)>& change) {
    model::Conditions c = servo.motion().conditions();
    change(c);
    servo.motion().set_conditions(c);
  }
  void reboot() {
    servo.advance_to(now);
    servo.reboot();
  }
};

/// e-Manual velocity-based profile from rest (includes/control_table_profile_velocity.md) in
/// register units: V in 0.229 rev/min, A in 214.577 rev/min², distance in pulses; position
/// travelled `t` ms after the start.
double emanual_velocity_profile(double v_reg, double a_reg, double distance, double t) {
  const double t1 = 64 * v_reg / a_reg;
  const double t2 = 64 * distance / v_reg;
  if (t1 >= t2) {                           // triangular: accelerate half way, decelerate the rest
    const double a = distance / (t2 * t1);  // a = V/(64·t1) pulses/ms², written via t1 and t2
    const double half = std::sqrt(distance / a);
    if (t <= half) {
      return a * t * t / 2;
    }
    const double rest = std::min(t, 2 * half) - half;
    return distance / 2 + a * half * rest - a * rest * rest / 2;
  }
  const double v = distance / t2;  // pulses/ms
  const double a = v / t1;
  const double t3 = t1 + t2;
  if (t <= t1) {
    return a * t * t / 2;
  }
  if (t <= t2) {
    return v * t1 / 2 + v * (t - t1);
  }
  const double d = std::min(t, t3) - t2;
  return v * t1 / 2 + v * (t2 - t1) + v * d - a * d * d / 2;
}

}  // namespace

TEST_CASE("A velocity-based trapezoidal move follows the e-Manual profile formulas",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("profile_velocity", 100) == kOk);
  REQUIRE(rig.write("profile_acceleration", 20) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  constexpr double kDistance = 1800;
  rig.at(10);
  REQUIRE(rig.write("goal_position", start + static_cast<std::int64_t>(kDistance)) == kOk);
  // t1 = 64·100/20 = 320 ms, t2 = 64·1800/100 = 1152 ms, t3 = 1472 ms.
  // Moving and Moving Status change at the first tick after the goal.
  for (double t = 16; t <= 1600; t += 16) {
    rig.at(10 + t);
    CAPTURE(t);
    // The model works in exact units (0.229 rev/min is 1/63.97 pulse/ms, the e-Manual writes 64):
    // within 0.1 % of the distance of the formula.
    CHECK(std::abs(static_cast<double>(rig.get("present_position") - start) -
                   emanual_velocity_profile(100, 20, kDistance, t)) <= kDistance * 1e-3 + 1);
    const std::int64_t status = rig.get("moving_status");
    CHECK((status & 0x30) == kTrapezoidal);
    if (t < 1440) {
      CHECK((status & kProfileOngoing) != 0);
      CHECK(rig.get("moving") == 1);
    }
  }
  CHECK(rig.get("present_position") == start + 1800);
  CHECK(rig.get("moving") == 0);
  CHECK(rig.get("moving_status") == (kTrapezoidal | kInPosition));
  CHECK(rig.get("position_trajectory") == start + 1800);
}

TEST_CASE("A short velocity-based move is triangular and peaks below Profile Velocity",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("profile_velocity", 200) == kOk);
  REQUIRE(rig.write("profile_acceleration", 10) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("goal_position", start - 500) == kOk);
  std::int64_t fastest = 0;
  for (double t = 1; t <= 3000; t += 1) {
    rig.at(t);
    CHECK(std::abs(static_cast<double>(start - rig.get("present_position")) -
                   emanual_velocity_profile(200, 10, 500, t)) <= 500 * 1e-3 + 1);
    fastest = std::max(fastest, std::abs(rig.get("present_velocity")));
  }
  CHECK((rig.get("moving_status") & 0x30) == kTriangular);
  CHECK(rig.get("present_position") == start - 500);
  // Peak velocity sqrt(a·d): a = 10/4096 pulse/ms², 500 pulses: 1.105 pulse/ms = 70.7 units.
  CHECK(fastest < 200);
  CHECK(std::abs(static_cast<double>(fastest) - 70.7) <= 1.5);
}

TEST_CASE("A time-based profile takes Profile Velocity ms with Profile Acceleration ms ramps",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("drive_mode", kTimeBased) == kOk);
  REQUIRE(rig.write("profile_velocity", 1000) == kOk);     // t3 = 1000 ms
  REQUIRE(rig.write("profile_acceleration", 300) == kOk);  // t1 = 300 ms
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("goal_position", start + 1400) == kOk);
  // Peak velocity 1400 / (1000 - 300) = 2 pulse/ms; half way through at t = 500 ms.
  rig.at(500);
  CHECK(rig.get("present_position") == start + 700);
  CHECK(rig.get("present_velocity") == std::llround(2.0 / (0.229 * kXPulsesPerRev / 60000)));
  rig.at(999);
  CHECK(rig.get("moving") == 1);
  rig.at(1001);
  CHECK(rig.get("present_position") == start + 1400);
  CHECK(rig.get("moving") == 0);
  CHECK(rig.get("moving_status") == (kTrapezoidal | kInPosition));
}

TEST_CASE("Velocity Control Mode ramps to Goal Velocity and integrates position",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kVelocityMode) == kOk);
  REQUIRE(rig.write("profile_acceleration", 50) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("goal_velocity", 100) == kOk);
  // Ramp time 64·100/50 = 128 ms, then 100 units (1.5633 pulse/ms) steadily.
  rig.at(64);
  CHECK(std::abs(rig.get("present_velocity") - 50) <= 1);
  rig.at(1128);
  CHECK(rig.get("present_velocity") == 100);
  const double unit = 0.229 * kXPulsesPerRev / 60000;
  const double expected = 100 * unit * (1128 - 128.0 / 2);
  CHECK(std::abs(static_cast<double>(rig.get("present_position") - start) - expected) <= 3);
  CHECK(rig.get("moving") == 1);
  REQUIRE(rig.write("goal_velocity", -100) == kOk);
  rig.wait(1000);
  CHECK(rig.get("present_velocity") == -100);
}

TEST_CASE("Extended Position Control Mode goes across turns with Homing Offset",
          "[model][motion]") {
  Rig rig("xm430-w350");
  // Position Control Mode keeps goals within the position limits.
  CHECK(rig.write("goal_position", 5000) == kDataRange);
  REQUIRE(rig.write("operating_mode", kExtendedMode) == kOk);
  REQUIRE(rig.write("homing_offset", 1000) == kOk);
  CHECK(rig.write("goal_position", 1'048'576) == kDataRange);
  CHECK(rig.write("goal_position", -1'048'575) == kOk);
  REQUIRE(rig.write("profile_velocity", 300) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_position", 3 * kTurn + 1000 + 7) == kOk);
  rig.wait(5000);
  CHECK(rig.get("present_position") == 3 * kTurn + 1000 + 7);
  REQUIRE(rig.write("goal_position", -2 * kTurn) == kOk);
  rig.wait(10000);
  CHECK(rig.get("present_position") == -2 * kTurn);
  // A reboot brings the position back within one turn, still offset by Homing Offset.
  rig.reboot();
  // The shaft was at -2 · 4096 - 1000: within one turn that is 3096, plus the offset.
  CHECK(rig.get("present_position") == 3096 + 1000);
  CHECK(rig.get("goal_position") == 3096 + 1000);
}

TEST_CASE("Reverse mode inverts goals and Present values but not Homing Offset",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kExtendedMode) == kOk);
  REQUIRE(rig.write("drive_mode", 0x01) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_position", start + 1000) == kOk);
  rig.wait(200);
  CHECK(rig.get("present_velocity") > 0);
  CHECK(rig.servo.motion().motor().velocity < 0);  // the shaft turns the other way
  rig.wait(3000);
  CHECK(rig.get("present_position") == start + 1000);
}

TEST_CASE("Changing Operating Mode resets the profile, Goal PWM and Goal Current",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("profile_velocity", 100) == kOk);
  REQUIRE(rig.write("profile_acceleration", 10) == kOk);
  REQUIRE(rig.write("goal_pwm", 100) == kOk);
  REQUIRE(rig.write("goal_current", 50) == kOk);
  REQUIRE(rig.write("operating_mode", kCurrentPositionMode) == kOk);
  CHECK(rig.get("profile_velocity") == 0);
  CHECK(rig.get("profile_acceleration") == 0);
  CHECK(rig.get("goal_pwm") == rig.get("pwm_limit"));
  CHECK(rig.get("goal_current") == rig.get("current_limit"));
  // Back to Position Control Mode: the position returns within one turn.
  rig.servo.table().set("present_position", 3 * kTurn + 10);
  REQUIRE(rig.write("operating_mode", kPositionMode) == kOk);
  CHECK(rig.get("present_position") == 10);
}

TEST_CASE("Changing Operating Mode leaves Goal Position as it was until torque on",
          "[model][motion]") {
  // The e-Manual's list of what a mode switch resets does not name Goal Position
  // (includes/control_table_opmode_six_2.md): a multi-turn goal outlives Extended Position mode.
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kExtendedMode) == kOk);
  REQUIRE(rig.write("goal_position", 5 * kTurn) == kOk);
  REQUIRE(rig.write("operating_mode", kVelocityMode) == kOk);
  CHECK(rig.get("goal_position") == 5 * kTurn);
  REQUIRE(rig.write("operating_mode", kPositionMode) == kOk);
  CHECK(rig.get("goal_position") == 5 * kTurn);
  // A write is judged by the mode of now, and torque on replaces the old goal with where the
  // shaft is.
  CHECK(rig.write("goal_position", 5 * kTurn) == kDataRange);
  rig.servo.table().set("present_position", 200);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  CHECK(rig.get("goal_position") == 200);
}

TEST_CASE("Torque on holds where the shaft is and wraps the position in Position mode",
          "[model][motion]") {
  Rig rig("xm430-w350");
  rig.servo.table().set("present_position", kTurn + 123);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  CHECK(rig.get("present_position") == 123);
  CHECK(rig.get("goal_position") == 123);
  rig.wait(500);
  CHECK(rig.get("present_position") == 123);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE("Torque off: the shaft stays put, or follows an external load", "[model][motion]") {
  Rig rig("xm430-w350");
  const std::int64_t start = rig.get("present_position");
  rig.wait(1000);
  CHECK(rig.get("present_position") == start);
  rig.conditions([](model::Conditions& c) { c.external_load_nm = -2.0; });
  rig.wait(100);
  CHECK(rig.get("present_position") < start);
  CHECK(rig.get("present_velocity") < 0);
  CHECK(rig.get("moving") == 1);
  CHECK(rig.get("present_current") == 0);
  // Torque on: the servo holds against the load, drawing current to do it.
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t held = rig.get("present_position");
  rig.wait(100);
  CHECK(std::abs(rig.get("present_position") - held) <= 1);
  // 2 N·m at 4.1 N·m / 2.3 A is 1.12 A: 417 units of 2.69 mA.
  CHECK(std::abs(rig.get("present_current") - 417) <= 2);
}

TEST_CASE("Goal Current caps torque in Current-based Position mode: a heavy load drags it",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kCurrentPositionMode) == kOk);
  REQUIRE(rig.write("goal_current", 100) == kOk);  // 0.269 A: about 0.48 N·m
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t held = rig.get("present_position");
  rig.conditions([](model::Conditions& c) { c.external_load_nm = 1.0; });
  rig.wait(200);
  CHECK(rig.get("present_position") > held + 50);
  CHECK((rig.get("moving_status") & kFollowingError) != 0);
  CHECK(std::abs(rig.get("present_current")) <= 100);
}

TEST_CASE("Profile Velocity 0 moves at the motor's own speed with no profile type",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("goal_position", start + 1000) == kOk);
  rig.wait(100);
  // No-load speed 46 rev/min at 12 V, here at 12.7 V: about 3.3 pulse/ms.
  CHECK(rig.get("present_velocity") > 190);
  CHECK((rig.get("moving_status") & 0x30) == 0);
  rig.wait(1000);
  CHECK(rig.get("present_position") == start + 1000);
}

TEST_CASE(
    "A blocked shaft heats the servo until Overheating shuts it down, and only Reboot "
    "after cooling recovers it",
    "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("shutdown", kHwOverheating) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  rig.conditions([](model::Conditions& c) { c.blocked = true; });
  REQUIRE(rig.write("goal_position", rig.get("present_position") + 1000) == kOk);
  rig.wait(100);
  CHECK(rig.get("present_position") == rig.get("goal_position") - 1000);
  // The current saturates at what the winding takes from the supply (2.3 A · 12.7 / 12).
  CHECK(rig.get("present_current") >= 880);
  double seconds = 0;
  while (rig.get("hardware_error_status") == 0 && seconds < 600) {
    rig.wait(1000);
    seconds += 1;
  }
  CHECK(seconds > 20);
  CHECK(seconds < 120);
  CHECK(rig.get("hardware_error_status") == kHwOverheating);
  CHECK(rig.get("present_temperature") >= rig.get("temperature_limit"));
  CHECK(rig.get("torque_enable") == 0);
  CHECK(rig.get("present_current") == 0);
  CHECK(rig.ping_error() == kAlert);
  CHECK(rig.write("torque_enable", 1) == (kResultFail | kAlert));
  // Still hot (in a hot room): a reboot clears the status, but the error comes straight back.
  rig.conditions([](model::Conditions& c) { c.ambient_c = 90; });
  rig.wait(30'000);
  rig.reboot();
  CHECK(rig.get("hardware_error_status") == 0);
  rig.wait(1);
  CHECK(rig.get("hardware_error_status") == kHwOverheating);
  CHECK(rig.write("torque_enable", 1) == (kResultFail | kAlert));
  // Cooled down: the error stays latched until a reboot, which then recovers the servo.
  rig.conditions([](model::Conditions& c) { c.ambient_c = 25; });
  rig.wait(600'000);
  CHECK(rig.get("present_temperature") < rig.get("temperature_limit"));
  CHECK(rig.get("hardware_error_status") == kHwOverheating);
  rig.reboot();
  rig.wait(1);
  CHECK(rig.get("hardware_error_status") == 0);
  CHECK(rig.write("torque_enable", 1) == kOk);
  CHECK(rig.ping_error() == kOk);
}

TEST_CASE(
    "A shaft held at the torque limit for a second raises Overload with the factory "
    "Shutdown",
    "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.get("shutdown") == 52);  // overload, electrical shock, overheating
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  rig.conditions([](model::Conditions& c) { c.blocked = true; });
  REQUIRE(rig.write("goal_position", 4000) == kOk);
  rig.wait(900);
  CHECK(rig.get("hardware_error_status") == 0);
  rig.wait(200);
  CHECK(rig.get("hardware_error_status") == kHwOverload);
  CHECK(rig.get("torque_enable") == 0);
  // The condition went with the torque: a reboot recovers.
  rig.reboot();
  rig.wait(10);
  CHECK(rig.get("hardware_error_status") == 0);
}

TEST_CASE("Input voltage outside the limits is an error only when Shutdown selects it",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  rig.conditions([](model::Conditions& c) { c.supply_v = 17.0; });
  rig.wait(10);
  CHECK(rig.get("present_input_voltage") == 170);
  CHECK(rig.get("hardware_error_status") == 0);  // the factory Shutdown (52) ignores voltage
  REQUIRE(rig.write("torque_enable", 0) == kOk);
  REQUIRE(rig.write("shutdown", 52 | kHwVoltage) == kOk);
  rig.wait(10);
  CHECK(rig.get("hardware_error_status") == kHwVoltage);
  CHECK(rig.ping_error() == kAlert);
  rig.conditions([](model::Conditions& c) { c.supply_v = 12.0; });
  rig.wait(10);
  CHECK(rig.get("hardware_error_status") == kHwVoltage);  // latched until a reboot
  rig.reboot();
  rig.wait(10);
  CHECK(rig.get("hardware_error_status") == 0);
  CHECK(rig.get("present_input_voltage") == 120);
}

TEST_CASE("An injected encoder error latches and comes back after Reboot while injected",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("shutdown", 52 | 0x08) == kOk);
  rig.servo.motion().set_injected(model::fault_set(model::HardwareFault::Encoder));
  rig.wait(1);
  CHECK(rig.get("hardware_error_status") == 0x08);
  rig.reboot();
  rig.wait(1);
  CHECK(rig.get("hardware_error_status") == 0x08);
  rig.servo.motion().set_injected(0);
  rig.reboot();
  rig.wait(1);
  CHECK(rig.get("hardware_error_status") == 0);
}

TEST_CASE("AX wheel mode turns by Moving Speed output with bit 10 for CW", "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.write("cw_angle_limit", 0) == kOk);
  REQUIRE(rig.write("ccw_angle_limit", 0) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("moving_speed", 1024 + 512) == kOk);  // 50 % CW
  rig.wait(500);
  const std::int64_t speed = rig.get("present_speed");
  CHECK((speed & 1024) != 0);
  // Half of the no-load speed (59 rev/min at 12 V, here 10 V): about 221 units of 0.111 rev/min.
  CHECK(std::abs((speed & 1023) - 221) <= 5);
  CHECK(rig.get("moving") == 1);
  const double before = rig.servo.motion().motor().position;
  rig.wait(500);
  CHECK(rig.servo.motion().motor().position < before);
  REQUIRE(rig.write("moving_speed", 0) == kOk);
  rig.wait(200);
  CHECK(rig.get("present_speed") == 0);
}

TEST_CASE("AX joint mode moves to Goal Position at Moving Speed, and the goal turns torque on",
          "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.write("moving_speed", 100) == kOk);  // 11.1 rev/min: 0.227 pulse/ms
  REQUIRE(rig.write("goal_position", 612) == kOk);
  CHECK(rig.get("torque_enable") == 1);
  rig.wait(200);
  CHECK(std::abs(rig.get("present_position") - (512 + 45)) <= 2);
  CHECK(rig.get("moving") == 1);
  rig.wait(1000);
  CHECK(rig.get("present_position") == 612);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE(
    "AX Alarm Shutdown zeroes Torque Limit while overheating and the error bit is in "
    "every status",
    "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.get("shutdown") == 36);                              // overload and overheating
  rig.conditions([](model::Conditions& c) { c.ambient_c = 75; });  // above the 70 °C limit
  rig.wait(600'000);
  CHECK(rig.get("present_temperature") >= 70);
  CHECK(rig.ping_error() == kV1Overheating);
  CHECK(rig.write("led", 1) == kV1Overheating);
  REQUIRE(rig.write("torque_enable", 1) == kV1Overheating);
  rig.wait(1);
  CHECK(rig.get("torque_limit") == 0);
  // Writing Torque Limit back while still hot does not last.
  REQUIRE(rig.write("torque_limit", 1023) == kV1Overheating);
  rig.wait(1);
  CHECK(rig.get("torque_limit") == 0);
  // Cool again: the error bit goes, and a written Torque Limit stays.
  rig.conditions([](model::Conditions& c) { c.ambient_c = 25; });
  rig.wait(600'000);
  CHECK(rig.ping_error() == kOk);
  REQUIRE(rig.write("torque_limit", 1023) == kOk);
  rig.wait(10);
  CHECK(rig.get("torque_limit") == 1023);
}

TEST_CASE("AX overload: a blocked shaft sets the Overload bit until Torque Limit is written",
          "[model][motion]") {
  Rig rig("ax-12a");
  rig.conditions([](model::Conditions& c) { c.blocked = true; });
  REQUIRE(rig.write("goal_position", 900) == kOk);
  rig.wait(1100);
  CHECK((rig.ping_error() & kV1Overload) != 0);
  CHECK(rig.get("torque_limit") == 0);
  rig.wait(100);
  CHECK((rig.ping_error() & kV1Overload) != 0);
  rig.conditions([](model::Conditions& c) { c.blocked = false; });
  REQUIRE(rig.write("torque_limit", 1023) == kOk);
  CHECK(rig.ping_error() == kOk);
  rig.wait(2000);
  CHECK(rig.get("present_position") == 900);
}

TEST_CASE(
    "The same instructions at the same times give the same tables bit for bit, ticked "
    "lazily or every millisecond",
    "[model][motion]") {
  const auto script = [](Rig& rig, bool eager) {
    const auto go = [&](double ms) {
      if (eager) {
        while (rig.now + milliseconds(1) <= sim::SimTime{} + milliseconds(static_cast<int>(ms))) {
          rig.wait(1);
        }
      }
      rig.at(ms);
    };
    rig.write("profile_velocity", 150);
    rig.write("profile_acceleration", 30);
    rig.write("torque_enable", 1);
    go(3);
    rig.write("goal_position", 3000);
    go(250.5);
    rig.write("goal_position", 100);  // velocity override mid-move
    rig.conditions([](model::Conditions& c) { c.external_load_nm = 0.7; });
    go(900);
    rig.conditions([](model::Conditions& c) { c.blocked = true; });
    rig.write("goal_position", 2500);
    go(4000);
    rig.conditions([](model::Conditions& c) { c.blocked = false; });
    go(9000);
    // Hot, then torque off: only the winding cools for minutes (ticks that step the temperature
    // alone), and a Protocol 1.0-style read of everything at the end.
    rig.write("torque_enable", 0);
    rig.conditions([](model::Conditions& c) {
      c.ambient_c = 30;
      c.external_load_nm = 0;
    });
    go(400'000);
  };
  Rig lazy("xm430-w350");
  Rig eager("xm430-w350");
  Rig again("xm430-w350");
  script(lazy, false);
  script(eager, true);
  script(again, false);
  const auto image = [](const Rig& r) {
    const auto b = r.servo.table().bytes();
    return Bytes(b.begin(), b.end());
  };
  CHECK(image(lazy) == image(again));
  CHECK(image(lazy) == image(eager));
  CHECK(lazy.servo.motion().motor() == eager.servo.motion().motor());
  CHECK(std::abs(lazy.servo.motion().motor().temperature_c - 30) < 1);
}

TEST_CASE(
    "Current Control Mode spins the unloaded shaft up to its top speed, and a load "
    "balances it",
    "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", 0) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_current", 200) == kOk);  // 0.538 A: 0.96 N·m
  rig.wait(1000);
  // Top speed at 12.7 V: 46 rev/min · 12.7 / 12 = 48.7 rev/min = 212.6 units.
  CHECK(std::abs(rig.get("present_velocity") - 213) <= 2);
  // A load larger than the motor's torque turns it back.
  rig.conditions([](model::Conditions& c) { c.external_load_nm = -2.0; });
  rig.wait(1000);
  CHECK(rig.get("present_velocity") < 0);
  CHECK(std::abs(rig.get("present_current")) <= 200);
}

TEST_CASE("PWM Control Mode runs at the share of the no-load speed Goal PWM gives",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", 16) == kOk);
  CHECK(rig.get("goal_pwm") == 885);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_pwm", -442) == kOk);  // 50 % backwards
  rig.wait(1000);
  CHECK(std::abs(rig.get("present_velocity") + 106) <= 2);
  CHECK(std::abs(rig.get("present_pwm") + 442) <= 5);
  REQUIRE(rig.write("goal_pwm", 0) == kOk);
  rig.wait(1000);
  CHECK(rig.get("present_velocity") == 0);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE("MX-28(2.0) reports Present Load in 0.1 % of the maximum torque", "[model][motion]") {
  Rig rig("mx-28-2");
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  rig.conditions([](model::Conditions& c) { c.external_load_nm = 1.25; });  // half of 2.5 N·m
  rig.wait(100);
  CHECK(rig.get("present_load") == -500);
}

TEST_CASE("A PH54 moves in its own units with its profile acceleration unit", "[model][motion]") {
  Rig rig("ph54-200-s500-r");
  REQUIRE(rig.write("profile_velocity", 1000) == kOk);      // 10 rev/min
  REQUIRE(rig.write("profile_acceleration", 2000) == kOk);  // 2000 rev/min²
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  const std::int64_t start = rig.get("present_position");
  REQUIRE(rig.write("goal_position", start + 200'000) == kOk);
  rig.wait(500);
  CHECK(rig.get("moving_status") == (kTrapezoidal | kProfileOngoing));
  CHECK(rig.get("present_velocity") == 1000);
  rig.wait(2000);
  CHECK(rig.get("present_position") == start + 200'000);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE("XL-320 shuts down through Hardware Error Status with its own bits", "[model][motion]") {
  Rig rig("xl-320");
  REQUIRE(rig.get("shutdown") == 3);  // overload and overheating
  REQUIRE(rig.write("shutdown", 7) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  rig.conditions([](model::Conditions& c) { c.supply_v = 10.0; });  // above 9.0 V
  rig.wait(10);
  CHECK(rig.get("hardware_error_status") == 0x04);
  CHECK(rig.get("torque_enable") == 0);
  CHECK(rig.ping_error() == kAlert);
}

TEST_CASE("A slower tick moves the shaft in coarser steps to the same place", "[model][motion]") {
  Servo servo(test::shipped_model("xm430-w350"), 1, milliseconds(10));
  CHECK(servo.motion().tick() == milliseconds(10));
  const auto write = [&](std::uint16_t address, Bytes data) {
    return servo
        .execute({Protocol::V2, 1, wire::Write{address, std::move(data)}},
                 model::Addressing::Unicast)
        .error;
  };
  REQUIRE(write(112, {100, 0, 0, 0}) == kOk);  // Profile Velocity
  REQUIRE(write(64, {1}) == kOk);
  REQUIRE(write(116, {0xE8, 0x0B, 0, 0}) == kOk);  // Goal Position 3048
  servo.advance_to(sim::SimTime{} + milliseconds(15));
  const std::int64_t at15 = servo.table().get("present_position");
  servo.advance_to(sim::SimTime{} + milliseconds(19));
  CHECK(servo.table().get("present_position") == at15);  // no tick between 10 and 20 ms
  servo.advance_to(sim::SimTime{} + milliseconds(20));
  CHECK(servo.table().get("present_position") > at15);
  servo.advance_to(sim::SimTime{} + std::chrono::seconds(2));
  CHECK(servo.table().get("present_position") == 3048);
}

TEST_CASE("Factory Reset re-initialises the table but not the shaft or the winding",
          "[model][motion]") {
  Rig rig("xm430-w350");
  rig.servo.table().set("present_position", 3000);
  rig.servo.table().set("present_temperature", 60);
  rig.wait(1);
  const auto r =
      rig.servo.execute({Protocol::V2, 1, wire::FactoryReset{0x02}}, model::Addressing::Unicast);
  REQUIRE(r.error == kOk);
  rig.wait(1);
  CHECK(rig.get("present_position") == 3000);
  CHECK(rig.get("present_temperature") >= 59);
}

TEST_CASE("Torque Limit 0 leaves an AX shaft free instead of coasting on", "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.write("goal_position", 1000) == kOk);
  rig.wait(50);
  REQUIRE(rig.get("moving") == 1);
  REQUIRE(rig.write("torque_limit", 0) == kOk);
  rig.wait(5);
  const std::int64_t stopped = rig.get("present_position");
  rig.wait(500);
  CHECK(rig.get("present_position") == stopped);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE("AX joint mode after wheel turns goes to the goal within the present turn",
          "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.write("cw_angle_limit", 0) == kOk);
  REQUIRE(rig.write("ccw_angle_limit", 0) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("moving_speed", 1023) == kOk);
  rig.wait(5000);  // several turns
  REQUIRE(rig.write("moving_speed", 0) == kOk);
  rig.wait(500);
  REQUIRE(rig.write("ccw_angle_limit", 1023) == kOk);  // back to joint mode
  const std::int64_t here = rig.get("present_position");
  const std::int64_t goal = here < 900 ? here + 100 : here - 100;
  REQUIRE(rig.write("moving_speed", 0) == kOk);
  REQUIRE(rig.write("goal_position", goal) == kOk);
  rig.wait(500);  // 100 pulses at full speed take about 100 ms; a turn over a second
  CHECK(rig.get("present_position") == goal);
}

TEST_CASE("Torque On by Goal Update turns torque on and goes to the goal within one turn",
          "[model][motion]") {
  Rig rig("xm430-w350");
  rig.servo.table().set("present_position", 2 * kTurn + 100);
  REQUIRE(rig.write("drive_mode", 0x08) == kOk);
  REQUIRE(rig.write("goal_position", 300) == kOk);
  CHECK(rig.get("torque_enable") == 1);
  rig.wait(200);
  CHECK(rig.get("present_position") == 300);
}

TEST_CASE("Time-based Velocity Control Mode comes back to rest in Profile Acceleration ms",
          "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kVelocityMode) == kOk);
  REQUIRE(rig.write("drive_mode", kTimeBased) == kOk);
  REQUIRE(rig.write("profile_acceleration", 200) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_velocity", 100) == kOk);
  rig.wait(100);
  CHECK(std::abs(rig.get("present_velocity") - 50) <= 1);
  rig.wait(200);
  CHECK(rig.get("present_velocity") == 100);
  REQUIRE(rig.write("goal_velocity", 0) == kOk);
  rig.wait(201);
  CHECK(rig.get("present_velocity") == 0);
  CHECK(rig.get("moving") == 0);
}

TEST_CASE("Bus Watchdog expiry stops PWM Control Mode too", "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", 16) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_pwm", 400) == kOk);
  rig.wait(500);
  REQUIRE(rig.get("present_velocity") > 50);
  rig.servo.expire_bus_watchdog();
  rig.wait(500);
  CHECK(rig.get("goal_pwm") == 0);
  CHECK(rig.get("present_velocity") == 0);
}

TEST_CASE("Clear with torque on holds at the position within one turn", "[model][motion]") {
  Rig rig("xm430-w350");
  REQUIRE(rig.write("operating_mode", kExtendedMode) == kOk);
  REQUIRE(rig.write("torque_enable", 1) == kOk);
  REQUIRE(rig.write("goal_position", 3 * kTurn + 5) == kOk);
  rig.wait(5000);
  REQUIRE(rig.get("moving") == 0);
  const auto r = rig.servo.execute({Protocol::V2, 1, wire::Clear{0x01, {0x44, 0x58, 0x4C, 0x22}}},
                                   model::Addressing::Unicast);
  REQUIRE(r.error == kOk);
  CHECK(rig.get("goal_position") == 5);
  rig.wait(1000);
  CHECK(rig.get("present_position") == 5);
}

TEST_CASE("AX compliance: a load deflects the held shaft by margin plus slope share",
          "[model][motion]") {
  Rig rig("ax-12a");
  REQUIRE(rig.write("goal_position", 512) == kOk);
  REQUIRE(rig.write("ccw_compliance_slope", 40) == kOk);  // representative value 32
  rig.conditions([](model::Conditions& c) { c.external_load_nm = 0.5; });
  rig.wait(200);
  // Margin 1 + slope 32 × 0.5 N·m / 1.5 N·m (Torque Limit 1023 of the stall torque): 11.7
  // pulses towards CCW.
  CHECK(rig.get("present_position") == 512 + 12);
  rig.conditions([](model::Conditions& c) { c.external_load_nm = 0; });
  rig.wait(200);
  CHECK(rig.get("present_position") == 512);
}

TEST_CASE("Instructions that only read leave a servo at rest, and a write wakes it",
          "[model][motion]") {
  Rig rig("xm430-w350");
  rig.wait(50);  // the first ticks settle the power-on state
  REQUIRE(rig.servo.motion().resting());
  const std::uint8_t id = rig.servo.id();
  const std::vector<wire::Instruction> reads = {
      wire::Ping{},
      wire::Read{132, 4},
      wire::SyncRead{132, 4, {id}},
      wire::FastSyncRead{{132, 4, {id}}},
      wire::BulkRead{{{id, 132, 4}}},
      wire::FastBulkRead{{{{id, 132, 4}}}},
  };
  for (const wire::Instruction& instruction : reads) {
    rig.servo.execute({Protocol::V2, id, instruction}, model::Addressing::Unicast);
    CHECK(rig.servo.motion().resting());
    rig.wait(5);
  }
  // A Write of a value equal to the present one still wakes it: whether a write changes what
  // the motion model reads is for its tick to find out.
  CHECK(rig.write("profile_velocity", rig.get("profile_velocity")) == kOk);
  CHECK_FALSE(rig.servo.motion().resting());
  rig.wait(5);
  CHECK(rig.servo.motion().resting());
  CHECK(rig.get("present_position") == 2048);
}
