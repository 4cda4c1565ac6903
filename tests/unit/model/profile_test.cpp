// The motion-profile planner (model/motion/profile.hpp) against the X-series e-Manual formulas
// (includes/control_table_profile_velocity.md, control_table_profile_acceleration.md,
// control_table_moving_status.md): velocity-based trapezoid, triangle and rectangle, time-based
// profiles and the 50% cap, velocity override, clamping and determinism.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "model/motion/profile.hpp"

using Catch::Matchers::WithinAbs;
using dxlemu::model::Profile;
using dxlemu::model::ProfilePoint;
using dxlemu::model::ProfileType;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// How close a sampled position must be to the closed form, pulses.
constexpr double kPositionTolerance = 1e-6;
/// How close a sampled velocity must be to the closed form, pulses/ms.
constexpr double kVelocityTolerance = 1e-9;
/// How close a computed duration must be to the e-Manual's, ms.
constexpr double kTimeTolerance = 1e-9;
/// Sampling step of the trajectory checks, ms.
constexpr double kStepMs = 0.37;

/// Profile Velocity(112) in 0.229 rev/min as pulses/ms: 0.229·4096/60000 is the e-Manual's 1/64.
double velocity_units(double profile_velocity) {
  return profile_velocity / 64;
}

/// Profile Acceleration(108) in 214.577 rev/min² as pulses/ms²: 214.577·4096/60000² is 1/4096.
double acceleration_units(double profile_acceleration) {
  return profile_acceleration / 4096;
}

/// Closed-form trapezoid from rest at 0 with the e-Manual's times: t1 = v/a (64·V/A),
/// t2 = ΔPos/v (64·ΔPos/V), t3 = t1 + t2.
ProfilePoint trapezoid(double t, double distance, double v, double a) {
  const double t1 = v / a;
  const double t2 = distance / v;
  const double t3 = t1 + t2;
  if (t < t1) {
    return {a * t * t / 2, a * t};
  }
  if (t < t2) {
    return {a * t1 * t1 / 2 + v * (t - t1), v};
  }
  if (t < t3) {
    return {distance - a * (t3 - t) * (t3 - t) / 2, a * (t3 - t)};
  }
  return {distance, 0};
}

/// Closed-form triangle from rest at 0: peak sqrt(a·ΔPos) at half of 2·sqrt(ΔPos/a).
ProfilePoint triangle(double t, double distance, double a) {
  const double total = 2 * std::sqrt(distance / a);
  if (t < total / 2) {
    return {a * t * t / 2, a * t};
  }
  if (t < total) {
    return {distance - a * (total - t) * (total - t) / 2, a * (total - t)};
  }
  return {distance, 0};
}

/// Checks that the velocity never jumps by more than `acceleration` allows between samples and
/// that the profile ends exactly on its goal, at rest.
void check_continuous_and_at_rest(const Profile& profile, double acceleration) {
  ProfilePoint previous = profile.at(0);
  for (double t = kStepMs; t < profile.duration_ms() + 10; t += kStepMs) {
    const ProfilePoint point = profile.at(t);
    CAPTURE(t);
    CHECK(std::abs(point.velocity - previous.velocity) <= acceleration * kStepMs + 1e-9);
    previous = point;
  }
  CHECK(profile.at(profile.duration_ms()).position == profile.goal());
  CHECK(profile.at(profile.duration_ms()).velocity == 0);
}

}  // namespace

TEST_CASE("A velocity-based trapezoid follows the e-Manual times and closed-form position",
          "[profile]") {
  const double profile_velocity = 100;
  const double profile_acceleration = 20;
  const double distance = 2048;
  const double v = velocity_units(profile_velocity);
  const double a = acceleration_units(profile_acceleration);
  const double t1 = 64 * profile_velocity / profile_acceleration;
  const double t2 = 64 * distance / profile_velocity;
  REQUIRE(t1 < t2);

  const Profile profile = Profile::velocity_based(1000, 0, 1000 + distance, v, a);
  CHECK(profile.type() == ProfileType::Trapezoidal);
  CHECK_THAT(profile.duration_ms(), WithinAbs(t1 + t2, kTimeTolerance));
  CHECK(profile.goal() == 1000 + distance);
  for (double t = 0; t < t1 + t2 + 50; t += kStepMs) {
    CAPTURE(t);
    const ProfilePoint expected = trapezoid(t, distance, v, a);
    const ProfilePoint point = profile.at(t);
    CHECK_THAT(point.position, WithinAbs(1000 + expected.position, kPositionTolerance));
    CHECK_THAT(point.velocity, WithinAbs(expected.velocity, kVelocityTolerance));
  }
  CHECK_THAT(profile.at(t1).velocity, WithinAbs(v, kVelocityTolerance));
}

TEST_CASE("A short velocity-based move is triangular with peak velocity sqrt of a times distance",
          "[profile]") {
  const double profile_velocity = 100;
  const double profile_acceleration = 20;
  const double distance = 200;
  const double v = velocity_units(profile_velocity);
  const double a = acceleration_units(profile_acceleration);
  // e-Manual: triangular when t1 >= t2; the peak then stays below the Profile Velocity.
  REQUIRE(64 * profile_velocity / profile_acceleration >= 64 * distance / profile_velocity);

  const Profile profile = Profile::velocity_based(0, 0, distance, v, a);
  const double total = 2 * std::sqrt(distance / a);
  CHECK(profile.type() == ProfileType::Triangular);
  CHECK_THAT(profile.duration_ms(), WithinAbs(total, kTimeTolerance));
  CHECK_THAT(profile.at(total / 2).velocity, WithinAbs(std::sqrt(a * distance), 1e-9));
  CHECK(std::sqrt(a * distance) < v);
  for (double t = 0; t < total + 50; t += kStepMs) {
    CAPTURE(t);
    const ProfilePoint expected = triangle(t, distance, a);
    CHECK_THAT(profile.at(t).position, WithinAbs(expected.position, kPositionTolerance));
    CHECK_THAT(profile.at(t).velocity, WithinAbs(expected.velocity, kVelocityTolerance));
  }
}

TEST_CASE("An infinite acceleration gives a rectangular move at the profile velocity",
          "[profile]") {
  const double v = velocity_units(100);
  const Profile profile = Profile::velocity_based(0, 0, 2048, v, kInfinity);
  CHECK(profile.type() == ProfileType::Rectangular);
  CHECK_THAT(profile.duration_ms(), WithinAbs(2048 / v, kTimeTolerance));
  for (double t = 0; t < profile.duration_ms(); t += kStepMs) {
    CAPTURE(t);
    CHECK(profile.at(t).velocity == v);
    CHECK_THAT(profile.at(t).position, WithinAbs(v * t, kPositionTolerance));
  }
  CHECK(profile.at(profile.duration_ms()).position == 2048);
  CHECK(profile.at(profile.duration_ms()).velocity == 0);

  SECTION("a profile acceleration of 0 counts as infinite") {
    const Profile zero = Profile::velocity_based(0, 0, 2048, v, 0);
    CHECK(zero.type() == ProfileType::Rectangular);
    CHECK(zero.duration_ms() == profile.duration_ms());
  }
}

TEST_CASE("Infinite velocity and acceleration is a step that reaches the goal at once",
          "[profile]") {
  const Profile profile = Profile::velocity_based(10, 0, 2048, kInfinity, kInfinity);
  CHECK(profile.type() == ProfileType::None);
  CHECK(profile.duration_ms() == 0);
  CHECK(profile.at(0).position == 2048);
  CHECK(profile.at(0).velocity == 0);
  CHECK(profile.at(-1).position == 10);

  SECTION("a profile velocity of 0 counts as infinite") {
    CHECK(Profile::velocity_based(10, 0, 2048, 0, 0).type() == ProfileType::None);
  }
  SECTION("a time-based span of 0 is a step too") {
    const Profile time_step = Profile::time_based(10, 0.5, 2048, 0, 100);
    CHECK(time_step.type() == ProfileType::None);
    CHECK(time_step.duration_ms() == 0);
    CHECK(time_step.at(0).position == 2048);
  }
}

TEST_CASE("Infinite velocity with finite acceleration accelerates then decelerates", "[profile]") {
  const double a = acceleration_units(20);
  const double distance = 5000;
  const Profile profile = Profile::velocity_based(0, 0, distance, kInfinity, a);
  CHECK(profile.type() == ProfileType::Triangular);
  CHECK_THAT(profile.duration_ms(), WithinAbs(2 * std::sqrt(distance / a), kTimeTolerance));
  for (double t = 0; t < profile.duration_ms() + 10; t += kStepMs) {
    CAPTURE(t);
    CHECK_THAT(profile.at(t).position,
               WithinAbs(triangle(t, distance, a).position, kPositionTolerance));
  }
}

TEST_CASE("A move in the negative direction mirrors the positive one", "[profile]") {
  const double v = velocity_units(100);
  const double a = acceleration_units(20);
  for (const double distance : {2048.0, 200.0}) {
    CAPTURE(distance);
    const Profile forward = Profile::velocity_based(0, 0, distance, v, a);
    const Profile backward = Profile::velocity_based(distance, 0, 0, v, a);
    CHECK(backward.type() == forward.type());
    CHECK(backward.duration_ms() == forward.duration_ms());
    for (double t = 0; t < forward.duration_ms() + 10; t += kStepMs) {
      CAPTURE(t);
      CHECK_THAT(backward.at(t).position,
                 WithinAbs(distance - forward.at(t).position, kPositionTolerance));
      CHECK_THAT(backward.at(t).velocity, WithinAbs(-forward.at(t).velocity, kVelocityTolerance));
    }
  }
  const Profile rectangle = Profile::velocity_based(0, 0, -1000, v, kInfinity);
  CHECK(rectangle.at(1).velocity == -v);
  CHECK(rectangle.at(rectangle.duration_ms()).position == -1000);
}

TEST_CASE("A time-based trapezoid lasts Profile Velocity ms and peaks at distance over t3 - t1",
          "[profile]") {
  const double total = 2000;
  const double accel = 500;
  const double distance = 3000;
  const double peak = distance / (total - accel);
  const Profile profile = Profile::time_based(0, 0, distance, total, accel);
  CHECK(profile.type() == ProfileType::Trapezoidal);
  CHECK(profile.duration_ms() == total);
  CHECK_THAT(profile.at(accel).velocity, WithinAbs(peak, kVelocityTolerance));
  CHECK_THAT(profile.at(total / 2).velocity, WithinAbs(peak, kVelocityTolerance));
  // The same trapezoid as velocity-based with v = peak and a = peak / t1: t1 = v/a, t2 = ΔPos/v.
  for (double t = 0; t < total + 10; t += kStepMs) {
    CAPTURE(t);
    const ProfilePoint expected = trapezoid(t, distance, peak, peak / accel);
    CHECK_THAT(profile.at(t).position, WithinAbs(expected.position, kPositionTolerance));
  }
  CHECK(profile.at(total).position == distance);
}

TEST_CASE("Time-based acceleration time is capped at half of the time span", "[profile]") {
  const Profile capped = Profile::time_based(0, 0, 3000, 2000, 1500);
  const Profile half = Profile::time_based(0, 0, 3000, 2000, 1000);
  CHECK(capped.type() == ProfileType::Triangular);
  CHECK(half.type() == ProfileType::Triangular);
  CHECK(capped.duration_ms() == 2000);
  CHECK_THAT(capped.at(1000).velocity, WithinAbs(3, kVelocityTolerance));
  for (double t = -1; t < 2010; t += kStepMs) {
    CAPTURE(t);
    CHECK(capped.at(t).position == half.at(t).position);
    CHECK(capped.at(t).velocity == half.at(t).velocity);
  }
}

TEST_CASE("A time-based profile without acceleration time is rectangular", "[profile]") {
  const Profile profile = Profile::time_based(100, 0, -400, 1000, 0);
  CHECK(profile.type() == ProfileType::Rectangular);
  CHECK(profile.duration_ms() == 1000);
  CHECK(profile.at(0).velocity == -0.5);
  CHECK_THAT(profile.at(500).position, WithinAbs(-150, kPositionTolerance));
  CHECK(profile.at(1000).position == -400);
}

TEST_CASE("Velocity override starts from the present velocity and ends at the goal at rest",
          "[profile]") {
  const double v = velocity_units(100);
  const double a = acceleration_units(20);

  SECTION("moving slowly toward the goal") {
    const Profile profile = Profile::velocity_based(0, 0.5, 2048, v, a);
    CHECK(profile.at(0).velocity == 0.5);
    CHECK(profile.type() == ProfileType::Trapezoidal);
    check_continuous_and_at_rest(profile, a);
  }
  SECTION("moving away from the goal turns back") {
    const Profile profile = Profile::velocity_based(0, -1, 2048, v, a);
    CHECK(profile.at(0).velocity == -1);
    // It brakes over v0²/(2a) before coming back.
    CHECK_THAT(profile.at(1 / a).position, WithinAbs(-1 / (2 * a), kPositionTolerance));
    CHECK(profile.at(1 / a).velocity == 0);
    check_continuous_and_at_rest(profile, a);
  }
  SECTION("too fast to stop, it overshoots and comes back") {
    const Profile profile = Profile::velocity_based(0, 1.5, 100, v, a);
    const double stop = 1.5 * 1.5 / (2 * a);
    REQUIRE(stop > 100);
    CHECK(profile.at(0).velocity == 1.5);
    CHECK_THAT(profile.at(1.5 / a).position, WithinAbs(stop, kPositionTolerance));
    CHECK(profile.at(1.5 / a).velocity == 0);
    CHECK(profile.at(1.5 / a + 10).velocity < 0);
    CHECK(profile.type() == ProfileType::Triangular);
    check_continuous_and_at_rest(profile, a);
  }
  SECTION("already at the goal but moving, it stops and comes back") {
    const Profile profile = Profile::velocity_based(500, -0.8, 500, v, a);
    CHECK(profile.duration_ms() > 0);
    CHECK(profile.at(0.8 / a).position < 500);
    check_continuous_and_at_rest(profile, a);
  }
  SECTION("faster than the profile velocity, it first slows down to it") {
    const Profile profile = Profile::velocity_based(0, 3, 10000, v, a);
    const double slowed = (3 - v) / a;
    CHECK(profile.at(0).velocity == 3);
    CHECK_THAT(profile.at(slowed).velocity, WithinAbs(v, kVelocityTolerance));
    CHECK_THAT(profile.at(slowed + 1000).velocity, WithinAbs(v, kVelocityTolerance));
    CHECK(profile.type() == ProfileType::Trapezoidal);
    check_continuous_and_at_rest(profile, a);
  }
  SECTION("with an infinite acceleration the velocity jumps to the profile velocity") {
    const Profile profile = Profile::velocity_based(0, -1, 2048, v, kInfinity);
    CHECK(profile.at(0).velocity == v);
    CHECK(profile.at(-1).velocity == -1);
    CHECK(profile.type() == ProfileType::Rectangular);
  }
}

TEST_CASE("Time-based velocity override uses the limits of the same move from rest", "[profile]") {
  const double peak = 3000.0 / (2000 - 500);
  const Profile profile = Profile::time_based(0, 1, 3000, 2000, 500);
  const Profile same = Profile::velocity_based(0, 1, 3000, peak, peak / 500);
  CHECK(profile.duration_ms() == same.duration_ms());
  for (double t = 0; t < profile.duration_ms() + 10; t += kStepMs) {
    CHECK(profile.at(t).position == same.at(t).position);
  }
  CHECK(profile.at(0).velocity == 1);
  check_continuous_and_at_rest(profile, peak / 500);

  SECTION("with nothing to travel the present speed is braked within the acceleration time") {
    const Profile back = Profile::time_based(0, 1, 0, 2000, 500);
    CHECK_THAT(back.at(500).velocity, WithinAbs(0, kVelocityTolerance));
    CHECK_THAT(back.at(500).position, WithinAbs(250, kPositionTolerance));
    check_continuous_and_at_rest(back, 1.0 / 500);
  }
}

TEST_CASE("Position is monotonic during a plain move", "[profile]") {
  const double v = velocity_units(100);
  const double a = acceleration_units(20);
  for (const double goal : {2048.0, -2048.0, 200.0, -200.0, 0.001}) {
    CAPTURE(goal);
    const Profile profile = Profile::velocity_based(0, 0, goal, v, a);
    const double direction = goal > 0 ? 1 : -1;
    double previous = profile.at(0).position;
    for (double t = 0.01; t < profile.duration_ms() + 1; t += 0.01) {
      const ProfilePoint point = profile.at(t);
      CAPTURE(t);
      CHECK(direction * (point.position - previous) >= 0);
      CHECK(direction * point.velocity >= 0);
      previous = point.position;
    }
  }
}

TEST_CASE("Samples before 0 give the start and samples after the end give the goal at rest",
          "[profile]") {
  const Profile profile =
      Profile::velocity_based(100, 0.25, 900, velocity_units(100), acceleration_units(20));
  CHECK(profile.at(-5).position == 100);
  CHECK(profile.at(-5).velocity == 0.25);
  CHECK(profile.at(0).position == 100);
  CHECK(profile.at(profile.duration_ms()).position == 900);
  CHECK(profile.at(profile.duration_ms() + 1000).position == 900);
  CHECK(profile.at(profile.duration_ms() + 1000).velocity == 0);
  CHECK(profile.at(kInfinity).position == 900);
}

TEST_CASE("Nothing to travel is a hold with no duration and no profile type", "[profile]") {
  const Profile held = Profile::hold(42);
  CHECK(held.type() == ProfileType::None);
  CHECK(held.duration_ms() == 0);
  CHECK(held.goal() == 42);
  CHECK(held.at(0).position == 42);
  CHECK(held.at(100).velocity == 0);

  const Profile velocity = Profile::velocity_based(10, 0, 10, 1, 0.01);
  CHECK(velocity.type() == ProfileType::None);
  CHECK(velocity.duration_ms() == 0);
  const Profile time = Profile::time_based(10, 0, 10, 2000, 500);
  CHECK(time.type() == ProfileType::None);
  CHECK(time.duration_ms() == 0);
}

TEST_CASE("Two identical plans give bit-identical samples", "[profile]") {
  const double v = velocity_units(123);
  const double a = acceleration_units(37);
  const Profile first = Profile::velocity_based(17.5, 1.3, 101.25, v, a);
  const Profile second = Profile::velocity_based(17.5, 1.3, 101.25, v, a);
  REQUIRE(first.duration_ms() == second.duration_ms());
  for (double t = -1; t < first.duration_ms() + 1; t += 0.013) {
    const ProfilePoint x = first.at(t);
    const ProfilePoint y = second.at(t);
    CHECK_FALSE(std::isnan(x.position));
    CHECK_FALSE(std::isnan(x.velocity));
    CHECK(x.position == y.position);
    CHECK(x.velocity == y.velocity);
  }
}
