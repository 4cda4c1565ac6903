#include "model/motion_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace dxlemu::model {
namespace {

using Ms = std::chrono::duration<double, std::milli>;

// Operating Mode values (includes/control_table_opmode_six_2.md).
constexpr std::int64_t kModeCurrent = 0;
constexpr std::int64_t kModeVelocity = 1;
constexpr std::int64_t kModePosition = 3;
constexpr std::int64_t kModeExtended = 4;
constexpr std::int64_t kModeCurrentPosition = 5;
constexpr std::int64_t kModePwm = 16;

// Drive Mode bits (includes/control_table_drivemode.md).
constexpr std::int64_t kReverse = 0x01;
constexpr std::int64_t kTimeBased = 0x04;
constexpr std::int64_t kTorqueOnByGoalUpdate = 0x08;

// Moving Status bits (includes/control_table_moving_status.md).
constexpr std::int64_t kInPosition = 0x01;
constexpr std::int64_t kProfileOngoing = 0x02;
constexpr std::int64_t kFollowingError = 0x08;

// Extended Position Control Mode: 512 turns, -256 ~ 256 rev (X and MX(2.0)).
constexpr double kExtendedTurns = 256;
// In position: within this share of a turn of Goal Position once the profile is over. Following
// error: further than this share of a turn from the trajectory (docs/motion.md: chosen).
constexpr double kInPositionRev = 1.0 / 1024;
constexpr double kFollowingErrorRev = 1.0 / 36;

// Protocol 1.0 items: 0 ~ 1023 magnitudes with bit 10 for the CW (negative) direction.
constexpr std::int64_t kV1Magnitude = 1023;
constexpr std::int64_t kV1Cw = 1024;
// MX 1.0 multi-turn (both angle limits 4095) and its position range.
constexpr std::int64_t kMultiTurnLimit = 4095;
// Present Load of MX(2.0) without a current sensor: 0.1 % of the maximum torque.
constexpr double kLoadFullScale = 1000;
// EX-106+ Sensed Current: 512 is 0 A, 10 mA per unit.
constexpr std::int64_t kSensedCurrentZero = 512;
constexpr double kSensedCurrentUnitA = 0.01;
// MX 1.0 Goal Acceleration unit: 8.583 °/s².
constexpr double kMx1AccelerationDegS2 = 8.583;
constexpr double kMsPerSecond = 1000;
constexpr double kDeciVolt = 10;
constexpr std::int64_t kRealtimeTickWrap = 32768;
// Compliance Slope's smallest representative value (includes/control_table_compliance_slope.md).
constexpr std::int64_t kMinComplianceSlope = 2;

std::int64_t round_to(double v) {
  return static_cast<std::int64_t>(std::llround(v));
}

double sign_of(double v) {
  return v < 0 ? -1.0 : 1.0;
}

}  // namespace

struct MotionModel::Items {
  explicit Items(const ModelSpec& s)
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
        torque_limit(s.index_of("torque_limit")),
        current_limit(s.index_of("current_limit")),
        pwm_limit(s.index_of("pwm_limit")),
        velocity_limit(s.index_of("velocity_limit")),
        homing_offset(s.index_of("homing_offset")),
        multi_turn_offset(s.index_of("multi_turn_offset")),
        cw_angle_limit(s.index_of("cw_angle_limit")),
        ccw_angle_limit(s.index_of("ccw_angle_limit")),
        moving_threshold(s.index_of("moving_threshold")),
        temperature_limit(s.index_of("temperature_limit")),
        min_voltage_limit(s.index_of("min_voltage_limit")),
        max_voltage_limit(s.index_of("max_voltage_limit")),
        shutdown(s.index_of("shutdown")),
        hardware_error_status(s.index_of("hardware_error_status")),
        present_position(s.index_of("present_position")),
        present_velocity(s.index_of("present_velocity")),
        present_speed(s.index_of("present_speed")),
        present_current(s.index_of("present_current")),
        present_load(s.index_of("present_load")),
        present_pwm(s.index_of("present_pwm")),
        sensed_current(s.index_of("sensed_current")),
        velocity_trajectory(s.index_of("velocity_trajectory")),
        position_trajectory(s.index_of("position_trajectory")),
        moving(s.index_of("moving")),
        moving_status(s.index_of("moving_status")),
        present_voltage(s.index_of("present_input_voltage") ? s.index_of("present_input_voltage")
                                                            : s.index_of("present_voltage")),
        present_temperature(s.index_of("present_temperature")),
        realtime_tick(s.index_of("realtime_tick")),
        cw_compliance_margin(s.index_of("cw_compliance_margin")),
        ccw_compliance_margin(s.index_of("ccw_compliance_margin")),
        cw_compliance_slope(s.index_of("cw_compliance_slope")),
        ccw_compliance_slope(s.index_of("ccw_compliance_slope")) {}

  std::optional<std::size_t> operating_mode, control_mode, drive_mode, torque_enable, goal_position,
      goal_velocity, goal_current, goal_torque, goal_pwm, goal_acceleration, profile_velocity,
      profile_acceleration, moving_speed, torque_limit, current_limit, pwm_limit, velocity_limit,
      homing_offset, multi_turn_offset, cw_angle_limit, ccw_angle_limit, moving_threshold,
      temperature_limit, min_voltage_limit, max_voltage_limit, shutdown, hardware_error_status,
      present_position, present_velocity, present_speed, present_current, present_load, present_pwm,
      sensed_current, velocity_trajectory, position_trajectory, moving, moving_status,
      present_voltage, present_temperature, realtime_tick, cw_compliance_margin,
      ccw_compliance_margin, cw_compliance_slope, ccw_compliance_slope;
};

MotionModel::MotionModel(ControlTable& table, sim::SimDuration tick)
    : table_(table),
      tick_(tick),
      next_tick_(sim::SimTime{} + tick),
      motor_(MotorParams::of(table.spec()), Ms(tick).count(), 0, 0),
      items_(std::make_unique<Items>(table.spec())) {
  const ModelSpec& spec = table_.spec();
  // The shaft starts where the table's initial Present Position says, at ambient temperature,
  // powered at the voltage the table's initial Present Voltage says.
  if (items_->present_temperature) {
    conditions_.ambient_c = static_cast<double>(spec.items[*items_->present_temperature].initial);
  }
  if (items_->present_voltage) {
    conditions_.supply_v =
        static_cast<double>(spec.items[*items_->present_voltage].initial) / kDeciVolt;
  }
  motor_.set_temperature(conditions_.ambient_c);
  if (items_->present_position) {
    motor_.set_position(static_cast<double>(spec.items[*items_->present_position].initial) -
                        static_cast<double>(homing()));
  }
  install_hooks();
  after_reboot();
}

MotionModel::~MotionModel() = default;

// --- hooks -------------------------------------------------------------------------------

void MotionModel::install_hooks() {
  const ModelSpec& spec = table_.spec();
  if (items_->goal_position) {
    table_.on_write("goal_position",
                    [this](std::size_t, std::int64_t, std::int64_t v) { on_goal_position(v); });
    // Extended and Current-based Position Control Mode take goals over 512 turns instead of
    // within the position limits (includes/control_table_opmode_six_2.md).
    if (items_->operating_mode &&
        (spec.family == Family::X || spec.family == Family::Mx2 || spec.family == Family::P)) {
      const ItemSpec& goal = spec.items[*items_->goal_position];
      const std::int64_t width_max = (std::int64_t{1} << (8 * goal.size - 1)) - 1;
      const std::int64_t turns =
          spec.family == Family::P ? width_max
                                   : round_to(kExtendedTurns * motor_.params().pulses_per_rev) - 1;
      table_.set_range_rule("goal_position", [this, turns](std::size_t) {
        const auto m = mode();
        return m == Mode::Extended || m == Mode::CurrentPosition
                   ? std::optional<ItemRange>(ItemRange{-turns, turns})
                   : std::nullopt;
      });
    }
  }
  if (items_->torque_enable) {
    table_.on_write("torque_enable", [this](std::size_t, std::int64_t o, std::int64_t n) {
      on_torque_enable(o, n);
    });
    // "REBOOT is the only method to reset Torque Enable to '1' after the shutdown"
    // (includes/control_table_shutdown.md): refused while Hardware Error Status holds an error.
    if (items_->hardware_error_status) {
      table_.add_validator("torque_enable", [this](std::size_t, std::int64_t v) {
        if (v != 0 && get(items_->hardware_error_status) != 0) {
          return TableResult::fail(TableError::ResultFail,
                                   "Torque Enable stays 0 after a hardware error shutdown until "
                                   "the servo reboots");
        }
        return TableResult{};
      });
    }
  }
  if (items_->operating_mode) {
    table_.on_write("operating_mode", [this](std::size_t, std::int64_t o, std::int64_t n) {
      if (o != n) {
        on_operating_mode();
      }
    });
  }
  if (items_->torque_limit && classic()) {
    // Alarm Shutdown zeroes Torque Limit; writing it again makes the motor usable
    // (ax-legacy-page-description-sections.md "Torque Limit").
    table_.on_write("torque_limit", [this](std::size_t, std::int64_t, std::int64_t) {
      overload_latched_ = false;
      v1_errors_ &=
          static_cast<std::uint8_t>(~fault_bit(table_.spec().family, HardwareFault::Overload));
    });
  }
}

void MotionModel::on_goal_position(std::int64_t goal) {
  wake();
  if (!torque_on()) {
    const bool by_goal = (get(items_->drive_mode) & kTorqueOnByGoalUpdate) != 0;
    // 1.0 families turn torque on when a goal is written; X with Torque On by Goal Update too.
    const bool auto_on = classic() ? table_.spec().family != Family::Xl320 : by_goal;
    if (!auto_on || get(items_->hardware_error_status) != 0 || !items_->torque_enable) {
      return;
    }
    table_.set(*items_->torque_enable, 1);
    velocity_demand_ = motor_.state().velocity;
    // Torque on in Position Control Mode resets the position within one turn, as for a write of
    // Torque Enable; the goal just written is then the target rather than the present position.
    if (mode() == Mode::Position && !classic()) {
      wrap_to_one_turn();
    }
  }
  if (position_mode()) {
    plan_to(raw_goal(goal));
  }
}

void MotionModel::on_torque_enable(std::int64_t old_value, std::int64_t new_value) {
  wake();
  if (old_value == new_value) {
    return;
  }
  if (new_value == 0) {
    profile_.reset();
    velocity_demand_ = 0;
    return;
  }
  velocity_demand_ = motor_.state().velocity;
  if (classic()) {
    // 1.0: the servo goes to Goal Position (which power-on set to where the shaft was).
    if (position_mode()) {
      plan_to(raw_goal(get(items_->goal_position)));
    }
    return;
  }
  // includes/control_table_opmode_note.md: torque on in Position Control Mode resets Present
  // Position to within one turn. The servo then holds where it is: Goal Position takes the
  // present position, so torque on never makes it jump (docs/motion.md).
  if (mode() == Mode::Position) {
    wrap_to_one_turn();
  }
  hold();
  publish();
}

void MotionModel::on_operating_mode() {
  wake();
  // includes/control_table_opmode_six_2.md: switching mode resets the profile and the limits.
  put(items_->profile_velocity, 0);
  put(items_->profile_acceleration, 0);
  if (items_->goal_pwm && items_->pwm_limit) {
    table_.set(*items_->goal_pwm, get(items_->pwm_limit));
  }
  if (items_->goal_current && items_->current_limit) {
    table_.set(*items_->goal_current, get(items_->current_limit));
  }
  if (mode() == Mode::Position) {
    wrap_to_one_turn();
  }
  profile_.reset();
  velocity_demand_ = 0;
  publish();
}

// --- state queries -------------------------------------------------------------------------

std::int64_t MotionModel::get(const std::optional<std::size_t>& item,
                              std::int64_t otherwise) const {
  return item ? table_.get(*item) : otherwise;
}

void MotionModel::put(const std::optional<std::size_t>& item, std::int64_t value) {
  if (!item) {
    return;
  }
  // Present values saturate at what the item can hold rather than wrap.
  const ItemSpec& spec = table_.spec().items[*item];
  const int bits = 8 * spec.size;
  const std::int64_t lo = spec.is_signed ? -(std::int64_t{1} << (bits - 1)) : 0;
  const std::int64_t hi =
      spec.is_signed ? (std::int64_t{1} << (bits - 1)) - 1 : (std::int64_t{1} << bits) - 1;
  table_.set(*item, std::clamp(value, lo, hi));
}

bool MotionModel::classic() const {
  return !items_->operating_mode;
}

std::optional<MotionModel::Mode> MotionModel::mode() const {
  if (classic()) {
    return wheel_mode() ? Mode::Pwm : Mode::Position;
  }
  switch (get(items_->operating_mode)) {
    case kModeCurrent:
      return Mode::Current;
    case kModeVelocity:
      return Mode::Velocity;
    case kModePosition:
      return Mode::Position;
    case kModeExtended:
      return Mode::Extended;
    case kModeCurrentPosition:
      return Mode::CurrentPosition;
    case kModePwm:
      return Mode::Pwm;
    default:
      return std::nullopt;
  }
}

bool MotionModel::wheel_mode() const {
  // XL-320 Control Mode 1 is wheel mode; 1.0 models are in wheel mode with both angle limits 0
  // (includes/control_table_mx_angle_limit.md).
  if (items_->control_mode) {
    return get(items_->control_mode) == 1;
  }
  return items_->cw_angle_limit && get(items_->cw_angle_limit) == 0 &&
         get(items_->ccw_angle_limit) == 0;
}

bool MotionModel::position_mode() const {
  const auto m = mode();
  return m == Mode::Position || m == Mode::Extended || m == Mode::CurrentPosition;
}

bool MotionModel::torque_on() const {
  return get(items_->torque_enable) != 0;
}

double MotionModel::direction() const {
  // Drive Mode bit 0 inverts positions, velocities, currents and PWM.
  return (get(items_->drive_mode) & kReverse) != 0 && !classic() ? -1.0 : 1.0;
}

double MotionModel::homing() const {
  return static_cast<double>(get(items_->homing_offset, get(items_->multi_turn_offset)));
}

double MotionModel::raw_goal(std::int64_t goal) const {
  // Present Position = direction · actual + Homing Offset.
  const double raw = direction() * (static_cast<double>(goal) - homing());
  if (!classic() || multi_turn()) {
    return raw;
  }
  // 1.0 joint mode reads and commands positions within one turn: the goal is in the turn the
  // shaft is in now (after turns in wheel mode, too).
  const double turn = motor_.params().pulses_per_rev;
  return std::floor(motor_.state().position / turn) * turn + raw;
}

bool MotionModel::multi_turn() const {
  return table_.spec().family == Family::Mx1 && get(items_->cw_angle_limit) == kMultiTurnLimit &&
         get(items_->ccw_angle_limit) == kMultiTurnLimit;
}

std::int64_t MotionModel::present_position() const {
  return round_to(direction() * motor_.state().position + homing());
}

double MotionModel::torque_cap() const {
  const MotorParams& p = motor_.params();
  if (classic()) {
    // Torque Limit: 0.1 % of the maximum torque.
    return p.stall_torque_nm * static_cast<double>(get(items_->torque_limit, kV1Magnitude)) /
           kV1Magnitude;
  }
  double cap = std::numeric_limits<double>::infinity();
  if (items_->current_limit && p.current_unit_a) {
    cap = static_cast<double>(get(items_->current_limit)) * *p.current_unit_a * p.torque_constant();
  }
  if (mode() == Mode::CurrentPosition && items_->goal_current && p.current_unit_a) {
    cap = std::min(cap, std::abs(static_cast<double>(get(items_->goal_current))) *
                            *p.current_unit_a * p.torque_constant());
  }
  return cap;
}

double MotionModel::duty_cap() const {
  if (!items_->pwm_limit) {
    return 1;
  }
  const ItemSpec& limit = table_.spec().items[*items_->pwm_limit];
  return static_cast<double>(get(items_->pwm_limit)) / static_cast<double>(limit.max);
}

double MotionModel::profile_elapsed_ms() const {
  // The profile at the time of the state: the last tick run.
  return Ms(state_time_ - profile_start_).count();
}

bool MotionModel::profile_running() const {
  return profile_ && profile_elapsed_ms() < profile_->duration_ms();
}

// --- profiles ------------------------------------------------------------------------------

void MotionModel::plan_to(double goal) {
  const MotorParams& p = motor_.params();
  const MotorState& s = motor_.state();
  const double top = motor_.top_speed(duty_cap(), conditions_.supply_v);
  const double fastest_acceleration = p.stall_torque_nm / p.inertia;
  const double inf = std::numeric_limits<double>::infinity();
  profile_start_ = state_time_;
  if (classic() || !items_->profile_velocity) {
    // 1.0 joint mode: Moving Speed (0: as fast as the motor goes); MX 1.0 Goal Acceleration
    // (0: no limit); PRO: Goal Velocity and no profile.
    const std::int64_t speed = items_->moving_speed ? get(items_->moving_speed) & kV1Magnitude
                                                    : std::abs(get(items_->goal_velocity));
    const double v = speed == 0 ? top : std::min(top, static_cast<double>(speed) * p.velocity_unit);
    double a = fastest_acceleration;
    if (const std::int64_t acc = get(items_->goal_acceleration); acc > 0 && classic()) {
      a = std::min(a, static_cast<double>(acc) * kMx1AccelerationDegS2 /
                          table_.spec().motion.degrees_per_pulse / (kMsPerSecond * kMsPerSecond));
    }
    profile_ = Profile::velocity_based(s.position, s.velocity, goal, v, a);
    return;
  }
  const auto velocity = static_cast<double>(get(items_->profile_velocity));
  const auto acceleration = static_cast<double>(get(items_->profile_acceleration));
  if (velocity == 0) {
    // No profile: the motor goes as fast as it can (Moving Status reports no profile).
    profile_ = Profile::velocity_based(s.position, s.velocity, goal, top, fastest_acceleration);
    step_profile_ = true;
    return;
  }
  step_profile_ = false;
  if ((get(items_->drive_mode) & kTimeBased) != 0) {
    profile_ = Profile::time_based(s.position, s.velocity, goal, velocity, acceleration);
    return;
  }
  const double a =
      acceleration == 0 || !p.acceleration_unit ? inf : acceleration * *p.acceleration_unit;
  profile_ = Profile::velocity_based(s.position, s.velocity, goal, velocity * p.velocity_unit, a);
}

void MotionModel::hold() {
  wake();
  const double here = motor_.state().position;
  profile_start_ = state_time_;
  profile_ = Profile::hold(here);
  step_profile_ = false;
  velocity_demand_ = 0;
  goal_to_present();
}

void MotionModel::goal_to_present() {
  if (!items_->goal_position) {
    return;
  }
  // Only where the goal could have been written: within the position limits in Position mode.
  const ItemSpec& goal = table_.spec().items[*items_->goal_position];
  const std::int64_t present = present_position();
  if (classic() || goal.in_range(present) || mode() == Mode::Extended ||
      mode() == Mode::CurrentPosition) {
    put(items_->goal_position, present);
  }
}

void MotionModel::republish() {
  publish();
}

void MotionModel::stop() {
  // Current and PWM Control Mode stop too: their goal goes to 0.
  if (mode() == Mode::Current) {
    put(items_->goal_current, 0);
  } else if (mode() == Mode::Pwm && !classic()) {
    put(items_->goal_pwm, 0);
  }
  hold();
}

void MotionModel::wrap_to_one_turn() {
  const double turn = motor_.params().pulses_per_rev;
  const double p = motor_.state().position;
  motor_.set_position(p - std::floor(p / turn) * turn);
}

void MotionModel::clear_turns() {
  wake();
  wrap_to_one_turn();
  profile_.reset();
  // A servo holding with torque on now holds at the wrapped position, not at the old goal.
  if (torque_on()) {
    hold();
  }
  publish();
}

void MotionModel::after_reboot() {
  // The table was just re-initialised: its Present values are not device-side changes.
  activity_ = Activity::Active;
  // includes/control_table_opmode_note.md: at power-on and reboot Present Position is within one
  // turn again (not for MX 1.0 multi-turn, whose position is absolute within its range).
  if (!classic()) {
    wrap_to_one_turn();
  }
  overload_latched_ = false;
  at_limit_ms_ = 0;
  profile_.reset();
  velocity_demand_ = 0;
  publish();
  goal_to_present();
  if (torque_on()) {
    hold();  // Startup Configuration turned torque on
  }
}

void MotionModel::set_conditions(const Conditions& conditions) {
  conditions_ = conditions;
  wake();
}

void MotionModel::set_injected(FaultSet faults) {
  injected_ = faults;
  wake();
}

// --- ticks ---------------------------------------------------------------------------------

void MotionModel::wake() {
  absorb_device_changes();
  activity_ = Activity::Active;
}

void MotionModel::absorb_device_changes() {
  // Present values set device-side (tests, the control API) move the physical state there.
  if (items_->present_position && table_.get(*items_->present_position) != published_.position) {
    published_.position = table_.get(*items_->present_position);
    motor_.set_position(raw_goal(published_.position));
    activity_ = Activity::Active;
  }
  if (items_->present_temperature &&
      table_.get(*items_->present_temperature) != published_.temperature) {
    published_.temperature = table_.get(*items_->present_temperature);
    motor_.set_temperature(static_cast<double>(published_.temperature));
    activity_ = Activity::Active;
  }
  if (items_->present_voltage && table_.get(*items_->present_voltage) != published_.voltage) {
    published_.voltage = table_.get(*items_->present_voltage);
    conditions_.supply_v = static_cast<double>(published_.voltage) / kDeciVolt;
    activity_ = Activity::Active;
  }
}

void MotionModel::advance_to(sim::SimTime now) {
  absorb_device_changes();
  while (next_tick_ <= now) {
    if (activity_ == Activity::Resting) {
      // Nothing changes until an input does: jump to the first tick after `now`.
      next_tick_ += ((now - next_tick_) / tick_ + 1) * tick_;
      state_time_ = next_tick_ - tick_;
      break;
    }
    if (activity_ == Activity::Cooling) {
      cool_until(now);
      break;
    }
    run_tick();
    next_tick_ += tick_;
  }
  if (items_->realtime_tick) {
    table_.set(
        *items_->realtime_tick,
        std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() %
            kRealtimeTickWrap);
  }
}

void MotionModel::run_tick() {
  const MotorState before = motor_.state();
  const bool was_running = profile_running();
  state_time_ = next_tick_;
  motor_.step(command(), conditions_);
  protect();
  publish();
  const MotorState& after = motor_.state();
  MotorState same_heat = before;
  same_heat.temperature_c = after.temperature_c;
  const bool still = after == same_heat && !was_running && !after.at_limit &&
                     (mode() == Mode::Velocity || velocity_demand_ == 0);
  if (!still) {
    activity_ = Activity::Active;
  } else if (after.temperature_c == before.temperature_c) {
    activity_ = Activity::Resting;
  } else {
    // Only the winding's temperature moves, and no current flows: cool_until() runs just that.
    activity_ = after.current_a == 0 ? Activity::Cooling : Activity::Active;
  }
}

void MotionModel::cool_until(sim::SimTime now) {
  // Equivalent to full ticks while the shaft is still and no current flows: each would only
  // step the temperature, whose relaxation is monotonic, so the errors it raises or clears are
  // those at the end (protect() once), and the Present values those at the end (publish() once).
  const auto ticks = (now - next_tick_) / tick_ + 1;
  bool settled = false;
  for (std::int64_t i = 0; i < ticks && !settled; ++i) {
    settled = motor_.cool(conditions_);
  }
  state_time_ = next_tick_ + (ticks - 1) * tick_;
  next_tick_ += ticks * tick_;
  protect();
  publish();
  if (settled) {
    activity_ = Activity::Resting;
  }
}

DriveCommand MotionModel::command() {
  if (!torque_on()) {
    return {};
  }
  return classic() ? classic_command() : modern_command();
}

DriveCommand MotionModel::classic_command() {
  DriveCommand c;
  c.torque_cap_nm = torque_cap();
  if (wheel_mode()) {
    // Wheel mode: Moving Speed is output, 0.1 % of the maximum, bit 10 for CW.
    const std::int64_t speed = get(items_->moving_speed);
    c.kind = DriveCommand::Kind::Pwm;
    c.duty = static_cast<double>(speed & kV1Magnitude) / kV1Magnitude *
             ((speed & kV1Cw) != 0 ? -1.0 : 1.0);
    return c;
  }
  c.kind = DriveCommand::Kind::Follow;
  c.target = profile_ ? profile_->at(profile_elapsed_ms()).position + compliance_offset()
                      : motor_.state().position;
  return c;
}

double MotionModel::compliance_offset() const {
  // AX, RX, EX (includes/control_table_compliance_slope.md): no torque within the Compliance
  // Margin, then torque rising over the Compliance Slope. Under an external load the shaft
  // settles where that torque meets the load: margin + slope × load / torque cap, on the side
  // the load pushes it (docs/motion.md).
  const double load = conditions_.external_load_nm;
  const double cap = torque_cap();
  if (!items_->cw_compliance_margin || load == 0 || cap <= 0) {
    return 0;
  }
  const bool ccw = load > 0;
  const auto margin =
      static_cast<double>(get(ccw ? items_->ccw_compliance_margin : items_->cw_compliance_margin));
  const std::int64_t slope_data =
      get(ccw ? items_->ccw_compliance_slope : items_->cw_compliance_slope);
  // "Data representative value is actually used": the power of two at or below it, at least 2.
  std::int64_t slope = kMinComplianceSlope;
  while (slope * 2 <= slope_data) {
    slope *= 2;
  }
  return sign_of(load) *
         (margin + static_cast<double>(slope) * std::min(1.0, std::abs(load) / cap));
}

DriveCommand MotionModel::modern_command() {
  DriveCommand c;
  c.torque_cap_nm = torque_cap();
  c.duty_cap = duty_cap();
  const MotorParams& p = motor_.params();
  const auto m = mode();
  if (!m) {
    return {};
  }
  switch (*m) {
    case Mode::Current: {
      c.kind = DriveCommand::Kind::Torque;
      const double units = static_cast<double>(get(items_->goal_current, get(items_->goal_torque)));
      c.torque_nm = direction() * units * p.current_unit_a.value_or(0) * p.torque_constant();
      return c;
    }
    case Mode::Pwm: {
      c.kind = DriveCommand::Kind::Pwm;
      const double full = items_->pwm_limit
                              ? static_cast<double>(table_.spec().items[*items_->pwm_limit].max)
                              : 1.0;
      c.duty = direction() * static_cast<double>(get(items_->goal_pwm)) / full;
      return c;
    }
    case Mode::Velocity: {
      // Velocity Control Mode ramps towards Goal Velocity with Profile Acceleration (0: a
      // step); time-based: Profile Acceleration is the time to reach it
      // (includes/control_table_profile_velocity.md, NOTE on Velocity Control Mode).
      const double goal =
          direction() * static_cast<double>(get(items_->goal_velocity)) * p.velocity_unit;
      const auto acc = static_cast<double>(get(items_->profile_acceleration));
      double rate = std::numeric_limits<double>::infinity();
      if (acc > 0 && (get(items_->drive_mode) & kTimeBased) != 0) {
        // A change of Goal Velocity takes Profile Acceleration ms: the rate is set when the goal
        // changes, from the velocity the ramp had then.
        if (goal != ramp_goal_) {
          ramp_goal_ = goal;
          ramp_rate_ = std::abs(goal - velocity_demand_) / acc;
        }
        rate = ramp_rate_;
      } else if (acc > 0 && p.acceleration_unit) {
        rate = acc * *p.acceleration_unit;
      }
      const double step = rate * motor_.tick_ms();
      const double diff = goal - velocity_demand_;
      velocity_demand_ = std::abs(diff) <= step ? goal : velocity_demand_ + sign_of(diff) * step;
      c.kind = DriveCommand::Kind::Follow;
      c.target = motor_.state().position + velocity_demand_ * motor_.tick_ms();
      return c;
    }
    case Mode::Position:
    case Mode::Extended:
    case Mode::CurrentPosition:
      c.kind = DriveCommand::Kind::Follow;
      c.target = profile_ ? profile_->at(profile_elapsed_ms()).position : motor_.state().position;
      return c;
  }
  return {};
}

// --- hardware errors -------------------------------------------------------------------------

void MotionModel::protect() {
  const Family family = table_.spec().family;
  const MotorState& s = motor_.state();
  const double tick_ms = motor_.tick_ms();
  at_limit_ms_ = s.at_limit && torque_on() ? at_limit_ms_ + tick_ms : 0;
  FaultSet active = injected_;
  const double volts = conditions_.supply_v * kDeciVolt;
  if (items_->min_voltage_limit && (volts < static_cast<double>(get(items_->min_voltage_limit)) ||
                                    volts > static_cast<double>(get(items_->max_voltage_limit)))) {
    active |= fault_set(HardwareFault::InputVoltage);
  }
  if (items_->temperature_limit &&
      s.temperature_c >= static_cast<double>(get(items_->temperature_limit))) {
    active |= fault_set(HardwareFault::Overheating);
  }
  if (at_limit_ms_ >= motor_.params().overload_ms) {
    active |= fault_set(HardwareFault::Overload);
    overload_latched_ = true;
  }
  if (classic() && !items_->hardware_error_status) {
    // 1.0 Alarm Shutdown: Torque Limit goes to 0 while a selected error is present
    // (includes/control_table_alarm_shutdown.md).
    if (overload_latched_) {
      active |= fault_set(HardwareFault::Overload);
    }
    if ((fault_bits(family, active) & get(items_->shutdown)) != 0) {
      put(items_->torque_limit, 0);
      at_limit_ms_ = 0;
    }
    v1_errors_ = fault_bits(family, active);
    return;
  }
  // X, MX(2.0), P, PRO, XL-320: an error selected in Shutdown latches in Hardware Error Status
  // and turns torque off; only a reboot clears it (includes/control_table_shutdown.md).
  const std::uint8_t selected = fault_bits(family, active) & get(items_->shutdown);
  const auto status = static_cast<std::uint8_t>(get(items_->hardware_error_status));
  if ((selected & ~status) != 0) {
    put(items_->hardware_error_status, status | selected);
    if (torque_on()) {
      table_.set(*items_->torque_enable, 0);
      profile_.reset();
      velocity_demand_ = 0;
    }
    at_limit_ms_ = 0;
  }
}

std::uint8_t MotionModel::v1_error_bits() const {
  if (!items_->hardware_error_status) {
    return v1_errors_;
  }
  // A 2.0 model speaking Protocol 1.0 shows its latched errors with the 1.0 bits.
  const Family family = table_.spec().family;
  const auto status = get(items_->hardware_error_status);
  std::uint8_t bits = 0;
  for (const HardwareFault f :
       {HardwareFault::InputVoltage, HardwareFault::Overheating, HardwareFault::Overload}) {
    if ((status & fault_bit(family, f)) != 0) {
      bits |= fault_bit(Family::Ax, f);
    }
  }
  return bits;
}

// --- present values --------------------------------------------------------------------------

void MotionModel::publish() {
  if (classic()) {
    publish_classic();
  } else {
    publish_modern();
  }
  put(items_->present_voltage, round_to(conditions_.supply_v * kDeciVolt));
  put(items_->present_temperature, round_to(motor_.state().temperature_c));
  published_.position = get(items_->present_position);
  published_.temperature = get(items_->present_temperature);
  published_.voltage = get(items_->present_voltage);
}

void MotionModel::publish_modern() {
  const MotorParams& p = motor_.params();
  const MotorState& s = motor_.state();
  const double dir = direction();
  put(items_->present_position, present_position());
  const std::int64_t velocity = round_to(dir * s.velocity / p.velocity_unit);
  put(items_->present_velocity, velocity);
  if (p.current_unit_a) {
    put(items_->present_current, round_to(dir * s.current_a / *p.current_unit_a));
  } else {
    put(items_->present_load, round_to(dir * s.torque_nm / p.stall_torque_nm * kLoadFullScale));
  }
  if (items_->pwm_limit) {
    put(items_->present_pwm,
        round_to(dir * s.duty * static_cast<double>(table_.spec().items[*items_->pwm_limit].max)));
  }
  const bool running = profile_running() && torque_on();
  const bool positional = position_mode() && torque_on();
  if (positional && profile_) {
    const ProfilePoint point = profile_->at(profile_elapsed_ms());
    put(items_->position_trajectory, round_to(dir * point.position + homing()));
    put(items_->velocity_trajectory, round_to(dir * point.velocity / p.velocity_unit));
  } else if (mode() == Mode::Velocity && torque_on()) {
    put(items_->velocity_trajectory, round_to(dir * velocity_demand_ / p.velocity_unit));
  }
  // includes/control_table_moving_2.md: Moving when |Present Velocity| > Moving Threshold, or
  // while a profile runs.
  put(items_->moving, running || std::abs(velocity) > get(items_->moving_threshold) ? 1 : 0);
  if (items_->moving_status) {
    std::int64_t status = 0;
    if (positional && profile_) {
      if (!step_profile_) {
        status |= static_cast<std::int64_t>(profile_->type());
      }
      if (running) {
        status |= kProfileOngoing;
      }
      const double turn = p.pulses_per_rev;
      const ProfilePoint point = profile_->at(profile_elapsed_ms());
      if (std::abs(point.position - s.position) > kFollowingErrorRev * turn) {
        status |= kFollowingError;
      }
      if (!running && std::abs(profile_->goal() - s.position) <= kInPositionRev * turn) {
        status |= kInPosition;
      }
    }
    put(items_->moving_status, status);
  }
}

void MotionModel::publish_classic() {
  const MotorParams& p = motor_.params();
  const MotorState& s = motor_.state();
  const ModelSpec& spec = table_.spec();
  if (items_->present_position) {
    const ItemSpec& item = spec.items[*items_->present_position];
    double position = s.position;
    if (!multi_turn()) {
      // Joint and wheel mode read the position within one turn; past the item's range (the
      // 60° dead zone of AX/RX) it reads as the range's end, 1023 (docs/motion.md).
      position -= std::floor(position / p.pulses_per_rev) * p.pulses_per_rev;
    }
    std::int64_t value = round_to(position + homing());
    if (item.max > item.min) {
      value = std::clamp(value, item.min, item.max);
    }
    put(items_->present_position, value);
  }
  const auto magnitude = [](double v) {
    const std::int64_t m = std::min(kV1Magnitude, round_to(std::abs(v)));
    return m | (m != 0 && v < 0 ? kV1Cw : 0);
  };
  put(items_->present_speed, magnitude(s.velocity / p.velocity_unit));
  put(items_->present_load, magnitude(s.torque_nm / p.stall_torque_nm * kV1Magnitude));
  put(items_->sensed_current, kSensedCurrentZero + round_to(s.current_a / kSensedCurrentUnitA));
  const bool running = profile_running() && torque_on();
  put(items_->moving, running || round_to(s.velocity / p.velocity_unit) != 0 ? 1 : 0);
}

}  // namespace dxlemu::model
