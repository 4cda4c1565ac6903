// Trajectories (keyframes sampled by interpolation), their playback on simulated time, and the
// range-of-motion sweep: the arithmetic every virtual hand runs on (docs/hands.md).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/hand/playback.hpp"
#include "model/hand/sweep.hpp"
#include "model/hand/trajectory.hpp"

using namespace dxlemu::model;

namespace trajectory_test_helpers {

/// A trajectory of one column "j" (degrees) through `values` at `times`.
Trajectory one_column(const std::vector<double>& times, const std::vector<double>& values) {
  std::vector<std::vector<double>> rows;
  rows.reserve(values.size());
  for (const double v : values) {
    rows.push_back({v});
  }
  return {{{"j", JointUnit::Degrees}}, times, rows};
}

/// Samples of column 0 every `step` seconds from the first keyframe to the last.
std::vector<Trajectory::Sample> dense(const Trajectory& t, Interpolation interpolation,
                                      double step = 0.001) {
  std::vector<Trajectory::Sample> samples;
  const auto count = static_cast<int>(std::lround(t.duration_s() / step));
  for (int i = 0; i <= count; ++i) {
    samples.push_back(t.at(0, i * step, interpolation));
  }
  return samples;
}

/// The joints of a sweep used below: degrees, and raw at its own speed.
std::vector<SweepJoint> sweep_joints() {
  return {{"shoulder_pan", JointUnit::Degrees, 10, -90, 90, 0, 60},
          {"gripper", JointUnit::Raw, 2048, 2000, 3000, 2048, 500}};
}

/// `t`'s two columns are `expected` (a row each) at `times`.
void check_two_columns(const Trajectory& t, const std::vector<std::vector<double>>& expected,
                       const std::vector<double>& times) {
  REQUIRE(t.row_count() == expected.size());
  for (std::size_t r = 0; r < expected.size(); ++r) {
    INFO("row " << r);
    CHECK(t.value(r, 0) == expected[r][0]);
    CHECK(t.value(r, 1) == expected[r][1]);
    CHECK(t.times_s()[r] == Approx(times[r]));
  }
}

}  // namespace trajectory_test_helpers

using trajectory_test_helpers::check_two_columns;
using trajectory_test_helpers::dense;
using trajectory_test_helpers::one_column;
using trajectory_test_helpers::sweep_joints;

TEST_CASE("A trajectory keeps its columns, keyframes, lines and origin", "[hand]") {
  const Trajectory t({{"shoulder_pan", JointUnit::Degrees}, {"3", JointUnit::Raw}}, {0.5, 1, 2},
                     {{1, 2048}, {2, 2100}, {3, 1900}}, {4, 6, 7}, "pick.csv", 2);
  CHECK(t.columns()[1] == TrajectoryColumn{"3", JointUnit::Raw});
  CHECK(t.find_column("3") == 1);
  CHECK(t.find_column("shoulder_pan") == 0);
  CHECK_FALSE(t.find_column("elbow"));
  CHECK(t.row_count() == 3);
  CHECK(t.value(2, 1) == 1900);
  CHECK(std::vector<double>(t.column_values(1).begin(), t.column_values(1).end()) ==
        std::vector<double>{2048, 2100, 1900});
  CHECK(t.line(1) == 6);
  CHECK(t.origin() == "pick.csv");
  CHECK(t.columns_line() == 2);
  CHECK(t.duration_s() == 2);
  // Built in code: every line is 0.
  CHECK(one_column({0, 1}, {0, 1}).line(1) == 0);
  CHECK(one_column({0, 1}, {0, 1}).columns_line() == 0);
}

TEST_CASE("Linear interpolation moves at constant speed between keyframes", "[hand]") {
  const Trajectory t = one_column({0, 2, 3}, {0, 10, 4});
  CHECK(t.at(0, 1, Interpolation::Linear).value == Approx(5));
  CHECK(t.at(0, 1, Interpolation::Linear).rate_per_s == Approx(5));
  CHECK(t.at(0, 2.5, Interpolation::Linear).value == Approx(7));
  CHECK(t.at(0, 2.5, Interpolation::Linear).rate_per_s == Approx(-6));
  // At a keyframe: its value exactly, and the rate of the segment that starts there.
  CHECK(t.at(0, 2, Interpolation::Linear).value == 10);
  CHECK(t.at(0, 2, Interpolation::Linear).rate_per_s == Approx(-6));
}

TEST_CASE("Cubic interpolation passes every keyframe exactly", "[hand]") {
  const std::vector<double> times{0, 0.3, 1, 1.1, 2.5, 4};
  const std::vector<double> values{0, 40, -20, -19, 90, 90};
  const Trajectory t = one_column(times, values);
  for (std::size_t k = 0; k < times.size(); ++k) {
    CHECK(t.at(0, times[k], Interpolation::Cubic).value == values[k]);
  }
}

TEST_CASE("Cubic interpolation never leaves the span of two neighbouring keyframes", "[hand]") {
  // Spikes, plateaus, a tiny step beside a large one, uneven spacing: where a natural spline
  // overshoots.
  const std::vector<double> times{0, 0.1, 0.2, 1, 1.05, 3, 3.01, 5};
  const std::vector<double> values{0, 100, 0, 0, 50, 51, -200, -200};
  const Trajectory t = one_column(times, values);
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double lo = std::min(values[k], values[k + 1]);
    const double hi = std::max(values[k], values[k + 1]);
    for (int i = 0; i <= 1000; ++i) {
      const double at = times[k] + (times[k + 1] - times[k]) * i / 1000;
      const double v = t.at(0, at, Interpolation::Cubic).value;
      INFO("segment " << k << " at " << at << " s");
      CHECK(v >= lo);
      CHECK(v <= hi);
    }
  }
}

TEST_CASE("On rising keyframes the cubic rises and its rate is never negative", "[hand]") {
  const Trajectory t = one_column({0, 0.5, 0.6, 2, 4, 4.5}, {-30, -29, 10, 10, 80, 81});
  const auto samples = dense(t, Interpolation::Cubic);
  for (std::size_t i = 1; i < samples.size(); ++i) {
    CHECK(samples[i].value >= samples[i - 1].value);
    CHECK(samples[i].rate_per_s >= 0);
  }
  // Falling keyframes: falling values, rates never positive.
  const Trajectory down = one_column({0, 1, 2}, {50, 20, -40});
  for (const auto& s : dense(down, Interpolation::Cubic)) {
    CHECK(s.rate_per_s <= 0);
  }
  CHECK(down.at(0, 1, Interpolation::Cubic).rate_per_s < 0);
}

TEST_CASE("The cubic's rate is its value's derivative and has no jump at a keyframe", "[hand]") {
  const Trajectory t = one_column({0, 1, 1.5, 3}, {0, 30, 35, -10});
  constexpr double kH = 1e-6;
  for (const double at : {0.2, 0.7, 1.2, 1.49, 2.2, 2.9}) {
    const double numeric = (t.at(0, at + kH, Interpolation::Cubic).value -
                            t.at(0, at - kH, Interpolation::Cubic).value) /
                           (2 * kH);
    INFO("at " << at << " s");
    CHECK(t.at(0, at, Interpolation::Cubic).rate_per_s == Approx(numeric).epsilon(1e-5));
  }
  for (const double keyframe : {1.0, 1.5}) {
    CHECK(t.at(0, keyframe - 1e-9, Interpolation::Cubic).rate_per_s ==
          Approx(t.at(0, keyframe, Interpolation::Cubic).rate_per_s).margin(1e-6));
  }
  // At a turning point (30 -> 35 -> -10) the keyframe is the peak: rate 0.
  CHECK(t.at(0, 1.5, Interpolation::Cubic).rate_per_s == 0);
}

TEST_CASE("A cubic starts from rest and comes to rest", "[hand]") {
  const Trajectory t = one_column({0, 1}, {0, 90});
  CHECK(t.at(0, 0, Interpolation::Cubic).rate_per_s == 0);
  CHECK(t.at(0, 1 - 1e-9, Interpolation::Cubic).rate_per_s == Approx(0).margin(1e-6));
  // Between, a smooth step: half way at half time, at 1.5 times the mean speed.
  CHECK(t.at(0, 0.5, Interpolation::Cubic).value == Approx(45));
  CHECK(t.at(0, 0.5, Interpolation::Cubic).rate_per_s == Approx(135));
}

TEST_CASE("Before the first keyframe and from the last on a trajectory holds at rate 0", "[hand]") {
  const Trajectory t = one_column({1, 2}, {20, 40});
  for (const auto interpolation : {Interpolation::Linear, Interpolation::Cubic}) {
    for (const double at : {-5.0, 0.0, 0.99, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
      CHECK(t.at(0, at, interpolation).value == 20);
      CHECK(t.at(0, at, interpolation).rate_per_s == 0);
    }
    for (const double at : {2.0, 2.01, 1e300, std::numeric_limits<double>::infinity()}) {
      CHECK(t.at(0, at, interpolation).value == 40);
      CHECK(t.at(0, at, interpolation).rate_per_s == 0);
    }
  }
  CHECK(t.duration_s() == 2);
}

TEST_CASE("A trajectory of one row is constant", "[hand]") {
  const Trajectory t = one_column({0}, {33});
  CHECK(t.duration_s() == 0);
  for (const double at : {-1.0, 0.0, 7.0}) {
    CHECK(t.at(0, at, Interpolation::Cubic).value == 33);
    CHECK(t.at(0, at, Interpolation::Linear).rate_per_s == 0);
  }
}

TEST_CASE("A trajectory refuses a malformed shape", "[hand]") {
  using Rows = std::vector<std::vector<double>>;
  const std::vector<TrajectoryColumn> j{{"j", JointUnit::Degrees}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(Trajectory({}, {0}, Rows{{}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {}, Rows{}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0, 1}, Rows{{1}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0, 1}, Rows{{1}, {1, 2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {-0.5, 1}, Rows{{1}, {2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {nan}, Rows{{1}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {1, 1}, Rows{{1}, {2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {1, 0.5}, Rows{{1}, {2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0, 1e-7}, Rows{{1}, {2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0, 2e9}, Rows{{1}, {2}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0}, Rows{{nan}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0}, Rows{{1e13}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory(j, {0, 1}, Rows{{1}, {2}}, {3}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory({{"", JointUnit::Raw}}, {0}, Rows{{1}}), std::invalid_argument);
  CHECK_THROWS_AS(Trajectory({{"a", JointUnit::Raw}, {"a", JointUnit::Degrees}}, {0}, Rows{{1, 2}}),
                  std::invalid_argument);
  // The least step is allowed.
  CHECK_NOTHROW(Trajectory(j, {0, Trajectory::kMinStepS}, Rows{{1}, {2}}));
}

TEST_CASE("Playback starts at its start time and runs at its speed", "[hand]") {
  const Trajectory t = one_column({0, 4}, {0, 40});
  const Playback linear{Interpolation::Linear, false, 1, 2};
  CHECK(trajectory_time(t, linear, 0) == 1);
  CHECK(trajectory_time(t, linear, 0.5) == 2);
  CHECK(trajectory_time(t, linear, -3) == 1);
  CHECK(play(t, linear, 0, 0.5).value == Approx(20));
  // 10 units per trajectory second, played twice as fast.
  CHECK(play(t, linear, 0, 0.5).rate_per_s == Approx(20));
  const Playback slow{Interpolation::Linear, false, 0, 0.25};
  CHECK(play(t, slow, 0, 4).value == Approx(10));
  CHECK(play(t, slow, 0, 4).rate_per_s == Approx(2.5));
}

TEST_CASE("Playback ends at the last keyframe and holds it at rest", "[hand]") {
  const Trajectory t = one_column({0, 4}, {0, 40});
  const Playback playback{Interpolation::Linear, false, 1, 2};
  CHECK_FALSE(ended(t, playback, 1.49));
  CHECK(ended(t, playback, 1.5));
  CHECK(trajectory_time(t, playback, 100) == 4);
  CHECK(play(t, playback, 0, 100).value == 40);
  CHECK(play(t, playback, 0, 100).rate_per_s == 0);
  // A start past the end has ended at once.
  CHECK(ended(t, Playback{Interpolation::Cubic, false, 9, 1}, 0));
}

TEST_CASE("A looping playback wraps around the duration and never ends", "[hand]") {
  const Trajectory t = one_column({1, 3}, {0, 20});
  const Playback loop{Interpolation::Linear, true, 2, 1};
  CHECK(trajectory_time(t, loop, 0.5) == 2.5);
  // The first pass starts at 2 s, the next ones at 0 s, where the first keyframe holds until 1 s.
  CHECK(trajectory_time(t, loop, 1) == 0);
  CHECK(trajectory_time(t, loop, 2.5) == 1.5);
  CHECK(trajectory_time(t, loop, 1 + 3 * 1000 + 2) == Approx(2));
  CHECK_FALSE(ended(t, loop, 1e6));
  CHECK(play(t, loop, 0, 2.5).value == Approx(5));
  CHECK(play(t, loop, 0, 2.5).rate_per_s == Approx(10));
  CHECK(play(t, loop, 0, 1.5).rate_per_s == 0);
  // Nothing to loop over: it holds.
  const Trajectory still = one_column({0}, {7});
  CHECK(trajectory_time(still, loop, 12) == 0);
  CHECK(play(still, loop, 0, 12).value == 7);
  CHECK_FALSE(ended(still, loop, 12));
}

TEST_CASE("A playback outside its ranges is refused", "[hand]") {
  CHECK_NOTHROW(check_playback(Playback{}));
  CHECK_THROWS_AS(check_playback(Playback{Interpolation::Cubic, false, -1, 1}),
                  std::invalid_argument);
  CHECK_THROWS_AS(check_playback(Playback{Interpolation::Cubic, false, 0, 0}),
                  std::invalid_argument);
  CHECK_THROWS_AS(check_playback(Playback{Interpolation::Cubic, false, 0,
                                          std::numeric_limits<double>::infinity()}),
                  std::invalid_argument);
}

TEST_CASE("A one-by-one sweep brings every joint to middle, then sweeps each in turn", "[hand]") {
  const Trajectory t = make_sweep(sweep_joints(), SweepOrder::OneByOne);
  CHECK(t.origin() == "sweep");
  CHECK(t.columns() == std::vector<TrajectoryColumn>{{"shoulder_pan", JointUnit::Degrees},
                                                     {"gripper", JointUnit::Raw}});
  const std::vector<std::vector<double>> expected{{10, 2048}, {0, 2048},  {-90, 2048}, {-90, 2048},
                                                  {90, 2048}, {90, 2048}, {0, 2048},   {0, 2000},
                                                  {0, 2000},  {0, 3000},  {0, 3000},   {0, 2048}};
  // Each move lasts its distance over the joint's speed, at least 0.1 s: both to middle in the
  // pan's 10 degrees at 60/s (the gripper is there already); the pan's 90, 180, 90 degrees; the
  // gripper's 48 (0.096 s, so 0.1), 1000, 952 pulses at 500/s. Each end is held 0.3 s.
  const double m = 1.0 / 6;
  const std::vector<double> times{0,       m,       m + 1.5, m + 1.8, m + 4.8, m + 5.1,
                                  m + 6.6, m + 6.7, m + 7.0, m + 9.0, m + 9.3, m + 11.204};
  check_two_columns(t, expected, times);
}

TEST_CASE("A sweep reaches low and high, ends at middle, and its times increase", "[hand]") {
  for (const auto order : {SweepOrder::OneByOne, SweepOrder::Together}) {
    const Trajectory t = make_sweep(sweep_joints(), order);
    for (std::size_t r = 1; r < t.row_count(); ++r) {
      CHECK(t.times_s()[r] > t.times_s()[r - 1]);
    }
    const auto joints = sweep_joints();
    for (std::size_t c = 0; c < joints.size(); ++c) {
      const auto values = t.column_values(c);
      CHECK(values.front() == joints[c].start);
      CHECK(values.back() == joints[c].middle);
      CHECK(*std::min_element(values.begin(), values.end()) == joints[c].low);
      CHECK(*std::max_element(values.begin(), values.end()) == joints[c].high);
      // Played cubic it stays within the range it sweeps (and the start).
      for (const auto interpolation : {Interpolation::Linear, Interpolation::Cubic}) {
        for (double at = 0; at <= t.duration_s(); at += 0.01) {
          const double v = t.at(c, at, interpolation).value;
          CHECK(v >= std::min(joints[c].low, joints[c].start));
          CHECK(v <= std::max(joints[c].high, joints[c].start));
        }
      }
    }
  }
}

TEST_CASE("A sweep holds each end long enough for a reader polling every 20 ms to see it",
          "[hand]") {
  // LeRobot's record_ranges_of_motion reads about every 20 ms, at times that have nothing to do
  // with the sweep's keyframes: whatever its phase, some reading falls on each end.
  constexpr double kPollS = 0.02;
  for (const auto order : {SweepOrder::OneByOne, SweepOrder::Together}) {
    const Trajectory t = make_sweep(sweep_joints(), order);
    const auto joints = sweep_joints();
    for (const double phase : {0.0, 0.003, 0.0071, 0.0137, 0.0199}) {
      for (std::size_t c = 0; c < joints.size(); ++c) {
        double low = joints[c].start;
        double high = joints[c].start;
        for (double at = phase; at <= t.duration_s(); at += kPollS) {
          const double v = t.at(c, at, Interpolation::Linear).value;
          low = std::min(low, v);
          high = std::max(high, v);
        }
        INFO("column " << c << ", phase " << phase);
        CHECK(low == joints[c].low);
        CHECK(high == joints[c].high);
      }
    }
  }
}

TEST_CASE("A sweep of all joints together aligns their keyframes on the slowest", "[hand]") {
  const Trajectory t = make_sweep(sweep_joints(), SweepOrder::Together);
  const std::vector<std::vector<double>> expected{{10, 2048}, {0, 2048},  {-90, 2000}, {-90, 2000},
                                                  {90, 3000}, {90, 3000}, {0, 2048}};
  // Each move as long as the slower joint's: 10/60 s, 1.5 s (pan; gripper 0.096 s), 3 s (pan;
  // gripper 2 s), 1.904 s (gripper; pan 1.5 s); both ends held 0.3 s by both joints.
  const double m = 1.0 / 6;
  const std::vector<double> times{0, m, m + 1.5, m + 1.8, m + 4.8, m + 5.1, m + 7.004};
  check_two_columns(t, expected, times);
}

TEST_CASE("A sweep with nothing to move still has increasing times", "[hand]") {
  const Trajectory t = make_sweep({{"1", JointUnit::Raw, 5, 5, 5, 5, 100}}, SweepOrder::OneByOne);
  REQUIRE(t.row_count() == 7);
  CHECK(t.duration_s() == Approx(4 * kMinSweepMoveS + 2 * kSweepHoldS));
  CHECK(play(t, Playback{}, 0, 0.25).value == 5);
}

TEST_CASE("A sweep refuses joints it cannot sweep", "[hand]") {
  const double inf = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(make_sweep({}, SweepOrder::Together), std::invalid_argument);
  CHECK_THROWS_AS(make_sweep({{"a", JointUnit::Degrees, 0, -10, 10, 0, 0}}, SweepOrder::Together),
                  std::invalid_argument);
  CHECK_THROWS_AS(make_sweep({{"a", JointUnit::Degrees, 0, 10, -10, 0, 60}}, SweepOrder::Together),
                  std::invalid_argument);
  CHECK_THROWS_AS(
      make_sweep({{"a", JointUnit::Degrees, inf, -10, 10, 0, 60}}, SweepOrder::Together),
      std::invalid_argument);
  CHECK_THROWS_AS(make_sweep({{"a", JointUnit::Degrees, 0, -10, 10, 0, 60},
                              {"a", JointUnit::Raw, 0, -10, 10, 0, 60}},
                             SweepOrder::OneByOne),
                  std::invalid_argument);
}
