#include "model/motion_items.hpp"

#include <initializer_list>
#include <string>

namespace dxlemu::model {

MotionItems::MotionItems(const ModelSpec& s)
    : operating_mode(s.index_of("operating_mode")),
      control_mode(s.index_of("control_mode")),
      drive_mode(s.index_of("drive_mode")),
      torque_enable(s.index_of("torque_enable")),
      goal_position(s.index_of("goal_position")),
      goal_velocity(s.index_of("goal_velocity")),
      goal_current(s.index_of("goal_current")),
      goal_torque(s.index_of("goal_torque")),
      goal_pwm(s.index_of("goal_pwm")),
      goal_acceleration(s.index_of("goal_acceleration")),
      profile_velocity(s.index_of("profile_velocity")),
      profile_acceleration(s.index_of("profile_acceleration")),
      moving_speed(s.index_of("moving_speed")),
      profile_time(s.index_of("profile_time")),
      profile_acceleration_time(s.index_of("profile_acceleration_time")),
      torque_limit(s.index_of("torque_limit")),
      current_limit(s.index_of("current_limit")),
      pwm_limit(s.index_of("pwm_limit")),
      velocity_limit(s.index_of("velocity_limit")),
      homing_offset(s.index_of("homing_offset")),
      multi_turn_offset(s.index_of("multi_turn_offset")),
      cw_angle_limit(s.index_of("cw_angle_limit")),
      ccw_angle_limit(s.index_of("ccw_angle_limit")),
      moving_threshold(s.index_of("moving_threshold")),
      min_position_limit(s.index_of("min_position_limit")),
      max_position_limit(s.index_of("max_position_limit")),
      temperature_limit(s.index_of("temperature_limit") ? s.index_of("temperature_limit")
                                                        : s.index_of("motor_temperature_limit")),
      min_voltage_limit(s.index_of("min_voltage_limit")),
      max_voltage_limit(s.index_of("max_voltage_limit")),
      shutdown(s.index_of("shutdown")),
      hardware_error_status(s.index_of("hardware_error_status")),
      error_code(s.index_of("error_code")),
      controller_state(s.index_of("controller_state")),
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
      moving(s.index_of("moving")),
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
                  ccw_angle_limit});
}

}  // namespace dxlemu::model
