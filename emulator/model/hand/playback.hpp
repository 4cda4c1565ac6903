#pragma once

#include <cstddef>

#include "model/hand/trajectory.hpp"

namespace dxlemu::model {

/// How a trajectory is played: which interpolation, from where, how fast, whether it repeats.
/// Maps simulated seconds since play started onto trajectory time; no clock of its own.
struct Playback {
  Interpolation interpolation = Interpolation::Cubic;
  /// At the end, start again from trajectory time 0 (start_s applies only to the first pass).
  bool loop = false;
  /// Where in the trajectory playing starts, seconds of trajectory time (>= 0, finite).
  double start_s = 0;
  /// Trajectory seconds per simulated second (> 0, finite): 2 plays twice as fast.
  double speed = 1;
  bool operator==(const Playback&) const = default;
};

/// Throws std::invalid_argument naming the field when `playback` breaks its documented ranges
/// (start_s negative or not finite, speed not more than 0 or not finite). The functions below
/// stay defined for any playback, but give meaningful answers only for a valid one.
void check_playback(const Playback& playback);

/// The trajectory time `elapsed_s` simulated seconds after play started (negative counts as 0):
/// start_s + elapsed_s * speed; with loop, wrapped into [0, duration) (a trajectory of duration
/// 0 just holds at 0), else clamped to [0, duration].
double trajectory_time(const Trajectory& trajectory, const Playback& playback, double elapsed_s);

/// Whether play has ended `elapsed_s` after it started: never while looping, else once trajectory
/// time reaches the duration. From then on the hand holds the last keyframe.
bool ended(const Trajectory& trajectory, const Playback& playback, double elapsed_s);

/// `column` of `trajectory` `elapsed_s` simulated seconds after play started: the value at
/// trajectory_time(), and its rate per simulated second (the trajectory's rate times speed; 0
/// once ended).
Trajectory::Sample play(const Trajectory& trajectory, const Playback& playback, std::size_t column,
                        double elapsed_s);

}  // namespace dxlemu::model
