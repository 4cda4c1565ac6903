#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "model/spec/model_spec.hpp"

namespace dxlemu::model {

/// The indices of the items a motion model reads and writes, looked up once per servo (a key
/// lookup costs a hash; a tick reads dozens of items). An item the model lacks is nullopt, and
/// whatever depends on it is not modelled.
struct MotionItems {
  /// The items of `spec` (Present Input Voltage, or Present Voltage on the 1.0 families).
  explicit MotionItems(const ModelSpec& spec);

  // Modes and goals.
  std::optional<std::size_t> operating_mode, control_mode, drive_mode, torque_enable, goal_position,
      goal_velocity, goal_current, goal_torque, goal_pwm, goal_acceleration, profile_velocity,
      profile_acceleration, moving_speed;
  // DYNAMIXEL-Y's time-based profile: its own items, used instead of Profile Velocity and
  // Profile Acceleration when Drive Mode selects a time-based profile.
  std::optional<std::size_t> profile_time, profile_acceleration_time;
  // Limits and offsets.
  std::optional<std::size_t> torque_limit, current_limit, pwm_limit, velocity_limit, homing_offset,
      multi_turn_offset, cw_angle_limit, ccw_angle_limit, moving_threshold, min_position_limit,
      max_position_limit;
  /// FEETECH's Phase, where the family reads a bit of it (FamilyTraits::full_angle_phase_bit).
  std::optional<std::size_t> phase;
  // Protection. `temperature_limit` is Motor Temperature Limit where the model has no single one
  // (DYNAMIXEL-Y); `error_code`, `error_code_history` and `controller_state` are DYNAMIXEL-Y's,
  // `servo_status` FEETECH's (the live error bits of its status packets).
  std::optional<std::size_t> temperature_limit, min_voltage_limit, max_voltage_limit, shutdown,
      hardware_error_status, error_code, controller_state, servo_status;
  // FEETECH's timed protections: Overload torque (1 % of full torque) held for Protection time
  // (10 ms) trips the overload protection, which leaves the motor Holding torque (1 %); Present
  // current at Protection current for Overcurrent protection time (10 ms) trips overcurrent.
  std::optional<std::size_t> overload_torque, overload_time, holding_torque, protection_current,
      overcurrent_time;
  /// Error Code History 1, 2, ... (oldest first), as many as the model has.
  std::vector<std::size_t> error_code_history;
  // Present values. `current` is MX 1.0 Current(68), a reading although the page makes it RW.
  // `present_temperature` is Present Motor Temperature where the model has no single one (the
  // winding is what the motor model heats; DYNAMIXEL-Y's Present Inverter Temperature stays at
  // its power-on value).
  std::optional<std::size_t> present_position, present_velocity, present_speed, present_current,
      present_load, present_pwm, sensed_current, current, velocity_trajectory, position_trajectory,
      moving, moving_status, present_voltage, present_temperature, realtime_tick;
  // Compliance (AX, RX, EX).
  std::optional<std::size_t> cw_compliance_margin, ccw_compliance_margin, cw_compliance_slope,
      ccw_compliance_slope;

  /// Counts of `present_voltage` per volt: 1 / its unit's figure ("0.01 [V]": 100), else 10
  /// (0.1 V, the unit of every page that prints none). Kept as counts per volt so that readings
  /// convert exactly (127 / 10 is 12.7; 127 * 0.1 is not).
  double voltage_counts_per_v = 1 / kDefaultVoltageUnitV;
  /// Milliseconds per unit of `profile_time` and `profile_acceleration_time`: their unit's
  /// figure (DYNAMIXEL-Y: "0.2 [ms]"), else 1.
  double profile_time_unit_ms = 1;

  /// The Present values above that the model has: every item the motion model writes.
  std::vector<std::size_t> readings() const;
  /// The settings the Present values are computed from (Homing Offset, Multi Turn Offset, Drive
  /// Mode, Moving Threshold, the angle limits that select MX 1.0 multi-turn, FEETECH's Phase):
  /// a write to one shows in them at once.
  std::vector<std::size_t> reading_settings() const;
};

}  // namespace dxlemu::model
