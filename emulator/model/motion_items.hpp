#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "model/model_spec.hpp"

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
  // Limits and offsets.
  std::optional<std::size_t> torque_limit, current_limit, pwm_limit, velocity_limit, homing_offset,
      multi_turn_offset, cw_angle_limit, ccw_angle_limit, moving_threshold;
  // Protection.
  std::optional<std::size_t> temperature_limit, min_voltage_limit, max_voltage_limit, shutdown,
      hardware_error_status;
  // Present values. `current` is MX 1.0 Current(68), a reading although the page makes it RW.
  std::optional<std::size_t> present_position, present_velocity, present_speed, present_current,
      present_load, present_pwm, sensed_current, current, velocity_trajectory, position_trajectory,
      moving, moving_status, present_voltage, present_temperature, realtime_tick;
  // Compliance (AX, RX, EX).
  std::optional<std::size_t> cw_compliance_margin, ccw_compliance_margin, cw_compliance_slope,
      ccw_compliance_slope;

  /// The Present values above that the model has: every item the motion model writes.
  std::vector<std::size_t> readings() const;
  /// The settings the Present values are computed from (Homing Offset, Multi Turn Offset, Drive
  /// Mode, Moving Threshold, the angle limits that select MX 1.0 multi-turn): a write to one
  /// shows in them at once.
  std::vector<std::size_t> reading_settings() const;
};

}  // namespace dxlemu::model
