#pragma once

#include <cstdint>
#include <vector>

namespace dxlemu::model {

/// Profile Type bits of Moving Status (bits 4-5).
enum class ProfileType : std::uint8_t {
  None = 0x00,
  Rectangular = 0x10,
  Triangular = 0x20,
  Trapezoidal = 0x30
};

/// A point of a profile: desired position and velocity.
struct ProfilePoint {
  double position = 0;  ///< pulses
  double velocity = 0;  ///< pulses/ms
};

/// A planned move: piecewise constant-acceleration segments from a start state to a goal, at rest
/// at the goal. The X-series "Profile" (includes/control_table_profile_velocity.md,
/// control_table_profile_acceleration.md, control_table_moving_status.md) as pure arithmetic: no
/// clocks, no I/O, no control-table knowledge. Units: position in pulses, time in ms since the
/// profile started, velocity in pulses/ms, acceleration in pulses/ms². The same inputs always give
/// bit-identical samples. Start, start velocity and goal must be finite; a limit that is not
/// positive (or NaN) counts as infinite, as 0 does in Profile Velocity/Acceleration.
class Profile {
 public:
  /// A profile that stays at `position` (nothing to do): duration 0, type None.
  static Profile hold(double position);
  /// Velocity-based profile (Drive Mode bit 2 = 0): from (start, start_velocity) to `goal` with at
  /// most `max_velocity` (> 0; +infinity = no limit, i.e. Profile Velocity 0 "step") and
  /// `acceleration` (> 0; +infinity = rectangular: the velocity jumps). Velocity override: a
  /// start_velocity that is not 0, possibly pointing away from the goal or too fast to stop before
  /// it, is handled by decelerating first (and coming back if the goal was overshot), keeping
  /// velocity continuous when acceleration is finite. A start velocity above max_velocity is first
  /// brought down to max_velocity. Nothing to travel and nothing to stop (goal == start, start
  /// velocity 0) gives hold(goal), as does goal == start with an infinite acceleration (the
  /// velocity jumps to 0 where the servo already is).
  static Profile velocity_based(double start, double start_velocity, double goal,
                                double max_velocity, double acceleration);
  /// Time-based profile (Drive Mode bit 2 = 1): the move from rest takes `total_ms` (Profile
  /// Velocity) with `accel_ms` (Profile Acceleration) of acceleration and as much of deceleration;
  /// accel_ms is capped at total_ms / 2 (e-Manual: "will not exceed 50% of Profile Velocity");
  /// accel_ms 0 = rectangular; total_ms 0 (or not finite) = step (velocity_based with infinite
  /// limits). With a non-zero start velocity the time span cannot be kept exactly, so the move is
  /// planned velocity_based with the peak velocity ΔPos / (total_ms - accel_ms) and the
  /// acceleration peak / accel_ms that the same move would have from rest; with nothing to travel
  /// (goal == start) the present speed is the peak and it is braked within accel_ms.
  static Profile time_based(double start, double start_velocity, double goal, double total_ms,
                            double accel_ms);

  /// Desired position and velocity `t_ms` after the profile started (clamped: before 0 = start
  /// and start velocity, from the end on = exactly the goal, at rest).
  ProfilePoint at(double t_ms) const;
  /// Time from start until the goal is reached, ms (0 for hold; 0 for an infinite-velocity step).
  double duration_ms() const { return duration_ms_; }
  /// What Moving Status reports: None for hold/step (Profile Velocity 0 with an infinite
  /// acceleration), Rectangular when acceleration is infinite, Triangular when the peak velocity
  /// stays below max_velocity (no cruise phase: the e-Manual's t1 >= t2, which includes an
  /// infinite max_velocity with finite acceleration), else Trapezoidal.
  ProfileType type() const { return type_; }
  /// The goal position, pulses.
  double goal() const { return goal_; }

 private:
  /// One constant-acceleration piece. Its velocity never changes sign inside it.
  struct Segment {
    double start_ms = 0;      ///< since the profile started
    double duration_ms = 0;   ///< > 0
    double position = 0;      ///< at the start, pulses
    double velocity = 0;      ///< at the start, pulses/ms
    double acceleration = 0;  ///< pulses/ms² (0 when cruising or after a velocity jump)
    double end_position = 0;  ///< at the end, pulses (the next segment's start)
    double end_velocity = 0;  ///< at the end, pulses/ms

    /// The point `tau_ms` into the segment, 0 <= tau_ms < duration_ms.
    ProfilePoint at(double tau_ms) const;
  };

  Profile(double start, double start_velocity, double goal, ProfileType type);

  /// Position and velocity where the last segment ends (the start state when there is none).
  ProfilePoint end_state() const;
  /// Appends a segment of `duration_ms` with `acceleration` that ends at `end_velocity` (given
  /// exactly, so cruise velocities and rest are not blurred by rounding). Ignores empty segments.
  void push(double duration_ms, double acceleration, double end_velocity);
  /// Appends the stop from the present velocity to rest with `acceleration` (> 0, finite).
  void brake(double acceleration);
  /// Appends the move from the present state to the goal, at rest there. The present velocity
  /// must point at the goal (or be 0) and be able to stop within the remaining distance.
  void approach(double max_velocity, double acceleration);
  /// Pins the end of the last segment to the goal, at rest, and sets the duration.
  void finish();

  std::vector<Segment> segments_;
  double start_ = 0;
  double start_velocity_ = 0;
  double goal_ = 0;
  double duration_ms_ = 0;
  ProfileType type_ = ProfileType::None;
};

}  // namespace dxlemu::model
