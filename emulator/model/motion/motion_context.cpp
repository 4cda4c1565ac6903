#include "model/motion/motion_context.hpp"

#include <algorithm>
#include <cmath>

#include "model/table/item_encoding.hpp"

namespace dxlemu::model {

MotionContext::MotionContext(ControlTable& table, sim::SimDuration tick)
    : table(table),
      traits(table.spec().traits()),
      items(table.spec()),
      motor(MotorParams::of(table.spec()), Ms(tick).count(), 0, 0) {}

void MotionContext::put(const std::optional<std::size_t>& item, std::int64_t value) {
  if (!item) {
    return;
  }
  const ItemSpec& spec = table.spec().items[*item];
  const ItemRange range = representable_range(spec);
  table.set(*item, std::clamp(value, range.min, range.max));
}

double MotionContext::direction() const {
  return traits.drive_mode_reverses && (get(items.drive_mode) & kDriveModeReverse) != 0 ? -1.0
                                                                                        : 1.0;
}

double MotionContext::homing() const {
  const auto offset = static_cast<double>(get(items.homing_offset, get(items.multi_turn_offset)));
  // FEETECH: "Present_Position = Actual_Position - Homing_Offset" (LeRobot feetech.py).
  return traits.homing_offset_subtracts ? -offset : offset;
}

std::int64_t MotionContext::present_position() const {
  const std::int64_t unwrapped = round_to(direction() * motor.state().position + homing());
  if (!single_turn_feedback()) {
    return unwrapped;
  }
  const auto turn = round_to(motor.params().pulses_per_rev);
  return ((unwrapped % turn) + turn) % turn;
}

bool MotionContext::single_turn_feedback() const {
  return items.phase && (get(items.phase) & traits.full_angle_phase_bit) == 0;
}

std::int64_t MotionContext::unwrapped(std::int64_t reading, Turn turn) const {
  if (!single_turn_feedback()) {
    return reading;
  }
  const double size = motor.params().pulses_per_rev;
  const double now = direction() * motor.state().position + homing();
  const double base = turn == Turn::Current
                          ? std::floor(std::round(now) / size) * size
                          : std::round((now - static_cast<double>(reading)) / size) * size;
  return reading + round_to(base);
}

std::int64_t MotionContext::current_reading(double amps) const {
  return table.spec().motion.current_zero + round_to(amps / motor.params().current_unit_a.value());
}

bool MotionContext::multi_turn() const {
  const auto& limit = traits.multi_turn_angle_limit;
  return limit && get(items.cw_angle_limit) == *limit && get(items.ccw_angle_limit) == *limit;
}

double MotionContext::duty_cap() const {
  if (!items.pwm_limit) {
    return 1;
  }
  const ItemSpec& limit = table.spec().items[*items.pwm_limit];
  return static_cast<double>(get(items.pwm_limit)) / static_cast<double>(limit.max);
}

double MotionContext::fastest_acceleration() const {
  const MotorParams& p = motor.params();
  return p.stall_torque_nm / p.inertia;
}

void MotionContext::wrap_to_one_turn() {
  const double turn = motor.params().pulses_per_rev;
  const double p = motor.state().position;
  motor.set_position(p - std::floor(p / turn) * turn);
}

ProfilePoint MotionContext::desired_point() const {
  if (profile) {
    return profile->at(profile_elapsed_ms());
  }
  return {motor.state().position, motor.state().velocity};
}

void MotionContext::plan_at_speed(double goal, double acceleration) {
  const MotorParams& p = motor.params();
  const MotorState& s = motor.state();
  const double top = motor.top_speed(duty_cap(), conditions.supply_v);
  const std::int64_t speed = items.moving_speed ? get(items.moving_speed) & kV1Magnitude
                                                : std::abs(get(items.goal_velocity));
  const double v = speed == 0 ? top : std::min(top, static_cast<double>(speed) * p.velocity_unit);
  profile_start = state_time;
  profile = Profile::velocity_based(s.position, s.velocity, goal, v, acceleration);
}

}  // namespace dxlemu::model
