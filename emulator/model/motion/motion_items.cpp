#include "model/motion/motion_items.hpp"

#include <initializer_list>
#include <string>

namespace dxlemu::model {
namespace {

// The first of `keys` the model has: DYNAMIXEL's key first, then another maker's name for the
// same item (FEETECH: torque_switch, running_speed, position_offset, ...; docs/feetech.md).
std::optional<std::size_t> first_of(const ModelSpec& s,
                                    std::initializer_list<std::string_view> keys) {
  for (const std::string_view key : keys) {
    if (const auto i = s.index_of(key)) {
      return i;
    }
  }
  return std::nullopt;
}

}  // namespace

MotionItems::MotionItems(const ModelSpec& s)
    : operating_mode(s.index_of("operating_mode")),
      control_mode(s.index_of("control_mode")),
      drive_mode(s.index_of("drive_mode")),
      torque_enable(first_of(s, {"torque_enable", "torque_switch"})),
      goal_position(s.index_of("goal_position")),
      goal_velocity(first_of(s, {"goal_velocity", "running_speed"})),
      goal_current(s.index_of("goal_current")),
      goal_torque(s.index_of("goal_torque")),
      goal_pwm(first_of(s, {"goal_pwm", "pwm_open_loop_speed"})),
      goal_acceleration(s.index_of("goal_acceleration")),
      profile_velocity(first_of(s, {"profile_velocity", "running_speed"})),
      profile_acceleration(first_of(s, {"profile_acceleration", "acceleration"})),
      moving_speed(s.index_of("moving_speed")),
      profile_time(s.index_of("profile_time")),
      profile_acceleration_time(s.index_of("profile_acceleration_time")),
      torque_limit(s.index_of("torque_limit")),
      current_limit(s.index_of("current_limit")),
      pwm_limit(s.index_of("pwm_limit")),
      velocity_limit(s.index_of("velocity_limit")),
      homing_offset(first_of(s, {"homing_offset", "position_offset"})),
      multi_turn_offset(s.index_of("multi_turn_offset")),
      cw_angle_limit(s.index_of("cw_angle_limit")),
      ccw_angle_limit(s.index_of("ccw_angle_limit")),
      moving_threshold(s.index_of("moving_threshold")),
      min_position_limit(first_of(s, {"min_position_limit", "minimum_angle_limit"})),
      max_position_limit(first_of(s, {"max_position_limit", "maximum_angle_limit"})),
      phase(s.traits().full_angle_phase_bit != 0 ? s.index_of("phase") : std::nullopt),
      temperature_limit(first_of(
          s, {"temperature_limit", "motor_temperature_limit", "maximum_temperature_limit"})),
      min_voltage_limit(first_of(s, {"min_voltage_limit", "minimum_input_voltage"})),
      max_voltage_limit(first_of(s, {"max_voltage_limit", "maximum_input_voltage"})),
      shutdown(first_of(s, {"shutdown", "unload_condition"})),
      hardware_error_status(s.index_of("hardware_error_status")),
      error_code(s.index_of("error_code")),
      controller_state(s.index_of("controller_state")),
      servo_status(s.index_of("servo_status")),
      overload_torque(s.index_of("overload_torque")),
      overload_time(s.index_of("protection_time")),
      holding_torque(s.index_of("holding_torque")),
      protection_current(s.index_of("protection_current")),
      overcurrent_time(s.index_of("overcurrent_protection_time")),
      present_position(s.index_of("present_position")),
      present_velocity(s.index_of("present_velocity")),
      present_speed(s.index_of("present_speed")),
      present_current(s.index_of("present_current")),
      present_load(s.index_of("present_load")),
      present_pwm(s.index_of("present_pwm")),
      sensed_current(s.index_of("sensed_current")),
      current(s.index_of("current")),
      velocity_trajectory(s.index_of("velocity_trajectory")),
      position_trajectory(s.index_of("position_trajectory")),
      moving(first_of(s, {"moving", "moving_flag"})),
      moving_status(s.index_of("moving_status")),
      present_voltage(s.index_of("present_input_voltage") ? s.index_of("present_input_voltage")
                                                          : s.index_of("present_voltage")),
      present_temperature(s.index_of("present_temperature")
                              ? s.index_of("present_temperature")
                              : s.index_of("present_motor_temperature")),
      realtime_tick(s.index_of("realtime_tick")),
      cw_compliance_margin(s.index_of("cw_compliance_margin")),
      ccw_compliance_margin(s.index_of("ccw_compliance_margin")),
      cw_compliance_slope(s.index_of("cw_compliance_slope")),
      ccw_compliance_slope(s.index_of("ccw_compliance_slope")) {
  for (int n = 1;; ++n) {
    const auto history = s.index_of("error_code_history_" + std::to_string(n));
    if (!history) {
      break;
    }
    error_code_history.push_back(*history);
  }
  if (profile_time) {
    profile_time_unit_ms = unit_figure(s.items[*profile_time].unit).value_or(1);
  }
  if (present_voltage) {
    voltage_counts_per_v =
        1 / unit_figure(s.items[*present_voltage].unit).value_or(kDefaultVoltageUnitV);
  }
}

namespace {

std::vector<std::size_t> present(std::initializer_list<std::optional<std::size_t>> items) {
  std::vector<std::size_t> out;
  for (const auto& item : items) {
    if (item) {
      out.push_back(*item);
    }
  }
  return out;
}

}  // namespace

std::vector<std::size_t> MotionItems::readings() const {
  return present({present_position, present_velocity, present_speed, present_current, present_load,
                  present_pwm, sensed_current, current, velocity_trajectory, position_trajectory,
                  moving, moving_status, present_voltage, present_temperature, realtime_tick});
}

std::vector<std::size_t> MotionItems::reading_settings() const {
  return present({homing_offset, multi_turn_offset, drive_mode, moving_threshold, cw_angle_limit,
                  ccw_angle_limit, phase});
}

}  // namespace dxlemu::model
