#pragma once

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "model/motion/motion_items.hpp"
#include "model/motion/motor_physics.hpp"
#include "model/motion/profile.hpp"
#include "model/spec/family_traits.hpp"
#include "model/table/control_table.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::model {

/// Milliseconds as a double: the motion model's unit of time.
using Ms = std::chrono::duration<double, std::milli>;

/// Protocol 1.0 items (Moving Speed, Torque Limit, Present Speed, Present Load): 0 ~ 1023
/// magnitudes, with bit 10 for the CW (negative) direction where they have one.
inline constexpr std::int64_t kV1Magnitude = 1023;
inline constexpr std::int64_t kV1Cw = 1024;
/// The voltage limits count 0.1 V (Present Input Voltage: MotionItems::voltage_counts_per_v).
inline constexpr double kDeciVolt = 10;
/// DYNAMIXEL-Y Moving Status bits beyond the X and P ones: Moving, Position In Range
/// (_includes/en/dxl/y/control_table_541_moving_status.md of ROBOTIS-GIT/emanual).
inline constexpr std::int64_t kMovingStatusMoving = 0x04;
inline constexpr std::int64_t kMovingStatusInRange = 0x40;
/// Drive Mode bits (includes/control_table_drivemode.md).
inline constexpr std::int64_t kDriveModeReverse = 0x01;
inline constexpr std::int64_t kDriveModeTimeBased = 0x04;
inline constexpr std::int64_t kDriveModeTorqueOnByGoal = 0x08;

/// `v` rounded to the nearest integer, halves away from zero.
inline std::int64_t round_to(double v) {
  return static_cast<std::int64_t>(std::llround(v));
}

/// -1 for negative values, else 1.
inline double sign_of(double v) {
  return v < 0 ? -1.0 : 1.0;
}

/// What the parts of one servo's motion model share: its control table and the items it reads,
/// its family's traits, the motor and its surroundings, and the move under way. MotionModel owns
/// it; its drive, protection and Present values read and change it.
struct MotionContext {
  /// The context for `table`, which must outlive it; the motor ticks every `tick`.
  MotionContext(ControlTable& table, sim::SimDuration tick);

  ControlTable& table;
  const FamilyTraits& traits;
  const MotionItems items;
  MotorPhysics motor;
  Conditions conditions;
  /// The last tick run (simulated time): the motor's state is from then.
  sim::SimTime state_time{};
  /// The move under way, and when it started (simulated time).
  std::optional<Profile> profile;
  sim::SimTime profile_start{};
  /// The profile is a step (Profile Velocity 0): Moving Status shows no profile type.
  bool step_profile = false;
  /// Velocity Control Mode: the ramped velocity, pulses/ms; also what a move starts from.
  double velocity_demand = 0;
  /// The most torque protection leaves the motor, a share of its stall torque: FEETECH's
  /// Holding torque while its overload protection holds; 1 otherwise.
  double protection_torque_share = 1;

  /// The item's value, or `otherwise` when the model lacks it.
  std::int64_t get(const std::optional<std::size_t>& item, std::int64_t otherwise = 0) const {
    return item ? table.get(*item) : otherwise;
  }
  /// Sets a Present value, saturated at what the item can hold rather than wrapped; nothing when
  /// the model lacks the item.
  void put(const std::optional<std::size_t>& item, std::int64_t value);

  bool torque_on() const { return get(items.torque_enable) != 0; }
  /// -1 when Drive Mode reverses the direction (FamilyTraits::drive_mode_reverses), else 1.
  double direction() const;
  /// Homing Offset (Multi Turn Offset on MX 1.0), pulses.
  double homing() const;
  /// Present Position as the motor's position shows: direction · position + Homing Offset,
  /// within one turn while the feedback is single-turn.
  std::int64_t present_position() const;
  /// FEETECH single-turn angle feedback: Phase's full-angle bit is clear, so Present Position
  /// wraps at 0 and one turn (FamilyTraits::full_angle_phase_bit).
  bool single_turn_feedback() const;
  /// Which turn a single-turn reading names.
  enum class Turn {
    /// The turn the shaft reads on now: a goal is a move of goal − Present Position.
    Current,
    /// The turn nearest the shaft: where a reading set from outside moves it least.
    Nearest,
  };
  /// `reading` (a Present Position value) counted over turns as direction · position + Homing
  /// Offset counts them: `reading` itself unless the feedback is single-turn, when `turn` says
  /// which of its turns it is.
  std::int64_t unwrapped(std::int64_t reading, Turn turn) const;
  /// What the model's current reading shows for `amps` (positive toward higher positions):
  /// motion.current_zero plus the current in the model's current unit, which it must have.
  std::int64_t current_reading(double amps) const;
  /// MX 1.0 multi-turn mode: both angle limits at the family's multi-turn value.
  bool multi_turn() const;
  /// PWM Limit as a fraction of the supply (1 without the item).
  double duty_cap() const;
  /// The most acceleration the motor gives, pulses/ms²: stall torque over inertia.
  double fastest_acceleration() const;
  /// How far the profile is at the time of the motor's state, ms.
  double profile_elapsed_ms() const { return Ms(state_time - profile_start).count(); }
  bool profile_running() const { return profile && profile_elapsed_ms() < profile->duration_ms(); }
  /// Where the servo wants the shaft at the time of the motor's state: the point of the move
  /// under way (a finished one holds its goal), or, with none, the shaft's own position and
  /// velocity. Pulses and pulses/ms.
  ProfilePoint desired_point() const;
  /// Moves the shaft back within one turn (reboot, Clear, torque on in Position Control Mode).
  void wrap_to_one_turn();
  /// A move to `goal` (pulses) at the speed of Moving Speed (0: as fast as the motor goes) or,
  /// without that item, |Goal Velocity| (PRO), accelerating at most at `acceleration`.
  void plan_at_speed(double goal, double acceleration);
};

}  // namespace dxlemu::model
