#pragma once

#include <memory>
#include <optional>
#include <string>

#include "model/hand/joint_scale.hpp"
#include "model/hand/playback.hpp"
#include "model/hand/trajectory.hpp"
#include "model/motion/hand.hpp"

namespace dxlemu::model {

/// What a hand is doing and where it came from, for the control API's `hand` and the logs.
enum class HandSource {
  File,   ///< a trajectory file (hand.play, --hand FILE)
  Sweep,  ///< a range-of-motion sweep (hand.sweep, --hand sweep)
  Move,   ///< a move of one joint (hand.move)
};

/// The one kind of hand there is: one column of a trajectory played back from a moment of
/// simulated time, in the servo's pulses through its JointScale, pushing with up to a force.
/// Every source (file, sweep, move) is a trajectory; many servos share one.
class TrajectoryHand : public Hand {
 public:
  /// Plays column `column` of `trajectory` as `playback` says from `start` on, on a servo of
  /// `scale`, pushing with up to `force_limit_nm`.
  TrajectoryHand(std::shared_ptr<const Trajectory> trajectory, std::size_t column,
                 const Playback& playback, sim::SimTime start, const JointScale& scale,
                 double force_limit_nm, HandSource source);

  std::optional<Grip> grip(sim::SimTime t) const override;
  bool still_from(sim::SimTime t) const override;

  const Trajectory& trajectory() const { return *trajectory_; }
  std::size_t column() const { return column_; }
  const Playback& playback() const { return playback_; }
  sim::SimTime start() const { return start_; }
  double force_limit_nm() const { return force_limit_nm_; }
  HandSource source() const { return source_; }
  /// The column's value at `t`, in the column's unit.
  double value_at(sim::SimTime t) const;
  /// Play has ended at `t` (never while looping): the hand holds the last keyframe.
  bool ended(sim::SimTime t) const;

 private:
  double elapsed_s(sim::SimTime t) const;

  std::shared_ptr<const Trajectory> trajectory_;
  std::size_t column_;
  Playback playback_;
  sim::SimTime start_;
  JointScale scale_;
  double force_limit_nm_;
  HandSource source_;
};

}  // namespace dxlemu::model
