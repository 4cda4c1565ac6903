#pragma once

#include <string>
#include <vector>

#include "model/hand/trajectory.hpp"

namespace dxlemu::model {

/// One joint of a range-of-motion sweep, values in `unit`.
struct SweepJoint {
  /// The joint as a trajectory column names it (a joint name or a decimal servo ID).
  std::string joint;
  JointUnit unit = JointUnit::Degrees;
  /// Where the shaft is when the sweep starts.
  double start = 0;
  /// The ends of the range to sweep (low <= high).
  double low = 0;
  double high = 0;
  /// Where the joint rests between sweeps and at the end.
  double middle = 0;
  /// How fast the hand moves this joint, units per second (> 0, finite).
  double speed_per_s = 0;
  bool operator==(const SweepJoint&) const = default;
};

/// The shortest move of a sweep, seconds.
inline constexpr double kMinSweepMoveS = 0.1;

/// How long the hand holds a joint still at each end of its range, seconds: as a person does
/// against a stop, and long enough for a reader polling much slower than the motion model
/// (LeRobot's record_ranges_of_motion reads about every 20 ms) to see the end itself rather than
/// a point on the way there and back. The same pause as the shipped calibration sweeps
/// (scripts/make_trajectories.py).
inline constexpr double kSweepHoldS = 0.3;

/// Whether the joints sweep in turn or all at once.
enum class SweepOrder { OneByOne, Together };

/// The hand of LeRobot's calibration: the person first brings every joint to the middle of its
/// range (what `set_half_turn_homings()` asks for), then moves each joint to one end of its range
/// and the other and back (what `record_ranges_of_motion()` records), so each joint goes
/// start -> middle -> low (held kSweepHoldS) -> high (held kSweepHoldS) -> middle. A trajectory
/// with origin "sweep", one column per joint in the order given, its first keyframe at 0 s, meant
/// to be played Linear (constant speed); its keyframes are the turning points and the ends of
/// the holds, so Cubic passes them too, slowing into each.
///
/// - OneByOne: all joints go from start to middle together (the slowest joint's time; the others
///   arrive at the same moment, slower than their speed), then joint 0 sweeps middle -> low,
///   holds, -> high, holds, -> middle while the others hold at middle, then joint 1, and so on.
/// - Together: the four moves are made by all joints at once, each move lasting as long as the
///   slowest joint needs for it, and the holds at low and high by all at once, so every joint
///   reaches its start, middle, low, high and middle at the same keyframe times.
///
/// Each move lasts its distance over the joint's speed but at least kMinSweepMoveS, so a move
/// of length 0 (a joint already at middle, low == middle) is a short hold and the keyframe times
/// stay strictly increasing. Throws std::invalid_argument for no joints, a speed that is not
/// positive and finite, a value that is not finite, low > high, or what Trajectory refuses.
Trajectory make_sweep(const std::vector<SweepJoint>& joints, SweepOrder order);

}  // namespace dxlemu::model
