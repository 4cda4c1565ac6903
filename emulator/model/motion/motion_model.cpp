#include "model/motion/motion_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "model/table/item_encoding.hpp"

namespace dxlemu::model {
namespace {

// Extended Position Control Mode: 512 turns, -256 ~ 256 rev (X and MX(2.0)).
constexpr double kExtendedTurns = 256;
constexpr std::int64_t kRealtimeTickWrap = 32768;

}  // namespace

MotionModel::MotionModel(ControlTable& table, sim::SimDuration tick)
    : tick_(tick),
      next_tick_(sim::SimTime{} + tick),
      motion_(table, tick),
      drive_(Drive::of(motion_)),
      protection_(motion_),
      present_(motion_) {
  const ModelSpec& spec = table.spec();
  const MotionItems& items = motion_.items;
  // The shaft starts where the table's initial Present Position says, at ambient temperature,
  // powered at the voltage the table's initial Present Voltage says.
  if (items.present_temperature) {
    motion_.conditions.ambient_c =
        static_cast<double>(spec.items[*items.present_temperature].initial);
  }
  if (items.present_voltage) {
    motion_.conditions.supply_v = static_cast<double>(spec.items[*items.present_voltage].initial) /
                                  items.voltage_counts_per_v;
  }
  motion_.motor.set_temperature(motion_.conditions.ambient_c);
  if (items.present_position) {
    motion_.motor.set_position(static_cast<double>(spec.items[*items.present_position].initial) -
                               motion_.homing());
  }
  after_reboot();
}

MotionModel::~MotionModel() = default;

// --- what writes of its items do ------------------------------------------------------------

std::optional<ItemRange> MotionModel::extended_goal_range() const {
  const auto m = drive_->mode();
  if (m != Mode::Extended && m != Mode::CurrentPosition) {
    return std::nullopt;
  }
  const std::int64_t turns =
      motion_.traits.extended_goals == ExtendedGoals::ItemWidth
          ? representable_range(motion_.table.spec().items[*motion_.items.goal_position]).max
          : round_to(kExtendedTurns * motion_.motor.params().pulses_per_rev) - 1;
  return ItemRange{-turns, turns};
}

void MotionModel::on_goal_position(std::int64_t goal) {
  wake();
  if (!motion_.torque_on() && !torque_on_by_goal()) {
    return;
  }
  if (position_mode()) {
    drive_->plan_to(goal_target(goal));
  }
}

void MotionModel::on_speed_goal() {
  wake();
  if (drive_->mode() == Mode::Velocity && !motion_.torque_on() &&
      motion_.traits.torque_on_by_speed_goal) {
    torque_on_by_goal();
  }
}

bool MotionModel::torque_on_by_goal() {
  const MotionItems& items = motion_.items;
  const TorqueOnByGoal by_goal = motion_.traits.torque_on_by_goal;
  const bool auto_on = by_goal == TorqueOnByGoal::Always ||
                       (by_goal == TorqueOnByGoal::DriveModeBit &&
                        (motion_.get(items.drive_mode) & kDriveModeTorqueOnByGoal) != 0);
  if (!auto_on || motion_.get(items.hardware_error_status) != 0 || !items.torque_enable) {
    return false;
  }
  motion_.table.set(*items.torque_enable, 1);
  motion_.velocity_demand = motion_.motor.state().velocity;
  // Torque on in Position Control Mode resets the position within one turn, as for a write of
  // Torque Enable; the goal just written is then the target rather than the present position.
  if (drive_->mode() == Mode::Position && motion_.traits.one_turn_at_torque_on) {
    motion_.wrap_to_one_turn();
  }
  return true;
}

double MotionModel::goal_target(std::int64_t goal) const {
  if (drive_->mode() == Mode::Step) {
    // FEETECH step mode: "the number of step progress is represented by parameter 0x2a", counted
    // from where the shaft is when the goal is written (docs/feetech.md "Motion").
    return motion_.motor.state().position + motion_.direction() * static_cast<double>(goal);
  }
  if (motion_.traits.goal_clamped_to_position_limits && drive_->mode() == Mode::Position) {
    goal = goal_within_limits(goal);
  }
  // Single-turn feedback: the position loop's error is the goal minus Present Position, so the
  // goal is a place on the turn the shaft reads on now.
  return drive_->raw_goal(motion_.unwrapped(goal, MotionContext::Turn::Current));
}

std::int64_t MotionModel::goal_within_limits(std::int64_t goal) const {
  const MotionItems& items = motion_.items;
  if (!items.min_position_limit || !items.max_position_limit) {
    return goal;
  }
  const std::int64_t lo = motion_.get(items.min_position_limit);
  const std::int64_t hi = motion_.get(items.max_position_limit);
  if (lo == 0 && hi == 0) {
    return goal;  // "0 when the multi-turn absolute position control is adopted"
  }
  if (!motion_.single_turn_feedback() || lo > hi) {
    return std::clamp(goal, lo, std::max(lo, hi));
  }
  // The goal as the angle it names, and, outside the limits, the limit fewer steps away around
  // the turn: a goal just past 4095 goes to a Minimum near 0, not to a Maximum far below it.
  const std::int64_t turn = round_to(motion_.motor.params().pulses_per_rev);
  const auto around = [turn](std::int64_t steps) { return ((steps % turn) + turn) % turn; };
  const std::int64_t angle = around(goal);
  if (angle >= lo && angle <= hi) {
    return angle;
  }
  return around(lo - angle) <= around(angle - hi) ? lo : hi;
}

void MotionModel::on_torque_enable(std::int64_t old_value, std::int64_t new_value) {
  wake();
  if (new_value == motion_.traits.calibrate_torque_value) {
    // STS/SMS Torque switch 128: "calibrate the current position to 2048". The flag is a command,
    // not a state: the item reads 0 afterwards, torque off (docs/feetech.md).
    motion_.table.set(*motion_.items.torque_enable, 0);
    calibrate_position(motion_.traits.calibrated_position);
    new_value = 0;
  }
  if (old_value == new_value) {
    return;
  }
  if (new_value == 0) {
    motion_.profile.reset();
    motion_.velocity_demand = 0;
    return;
  }
  motion_.velocity_demand = motion_.motor.state().velocity;
  if (motion_.traits.torque_on_goal == TorqueOnGoal::MovesToGoal && drive_->mode() != Mode::Step) {
    // The servo drives to Goal Position as it stands, a stale one too: power-on set it to where
    // the shaft was, and nothing since moved it with the shaft (docs/feetech.md).
    if (position_mode()) {
      drive_->plan_to(goal_target(motion_.get(motion_.items.goal_position)));
    }
    return;
  }
  // includes/control_table_opmode_note.md: torque on in Position Control Mode resets Present
  // Position to within one turn. The servo then holds where it is (TorqueOnGoal::Holds).
  if (drive_->mode() == Mode::Position && motion_.traits.one_turn_at_torque_on) {
    motion_.wrap_to_one_turn();
  }
  hold();
  publish();
}

void MotionModel::on_operating_mode() {
  wake();
  const MotionItems& items = motion_.items;
  // includes/control_table_opmode_six_2.md: switching mode resets the profile and the limits.
  if (motion_.traits.mode_change_resets_goals) {
    motion_.put(items.profile_velocity, 0);
    motion_.put(items.profile_acceleration, 0);
    if (items.goal_pwm && items.pwm_limit) {
      motion_.table.set(*items.goal_pwm, motion_.get(items.pwm_limit));
    }
    if (items.goal_current && items.current_limit) {
      motion_.table.set(*items.goal_current, motion_.get(items.current_limit));
    }
  }
  if (drive_->mode() == Mode::Position) {
    motion_.wrap_to_one_turn();
  }
  motion_.profile.reset();
  motion_.velocity_demand = 0;
  publish();
}

bool MotionModel::calibrate_position(std::int64_t present) {
  const auto& offset = motion_.items.homing_offset;
  if (!offset) {
    return true;
  }
  // The offset that makes Present Position read `present` where the shaft is now. One the item
  // cannot hold (a target far outside a turn) is refused as a written value out of range would
  // be, rather than clamped to an offset that reads something else (docs/feetech.md).
  const std::int64_t shaft = round_to(motion_.direction() * motion_.motor.state().position);
  std::int64_t value = motion_.traits.homing_offset_subtracts ? shaft - present : present - shaft;
  if (motion_.single_turn_feedback()) {
    // A single-turn reading repeats every turn: of the offsets that make it, the one nearest 0.
    const std::int64_t turn = round_to(motion_.motor.params().pulses_per_rev);
    if (present < 0 || present >= turn) {
      return false;
    }
    value -= round_to(static_cast<double>(value) / static_cast<double>(turn)) * turn;
  }
  if (!motion_.table.spec().items[*offset].in_range(value)) {
    return false;
  }
  motion_.put(offset, value);
  on_reading_setting();
  return true;
}

void MotionModel::on_reading_setting() {
  // The motor's state is that of the last tick; only how the table shows it changes.
  wake();
  publish();
}

// --- device-side changes -------------------------------------------------------------------

void MotionModel::setting_forced(std::size_t item) {
  const std::vector<std::size_t> settings = motion_.items.reading_settings();
  if (std::find(settings.begin(), settings.end(), item) != settings.end()) {
    on_reading_setting();
  }
}

void MotionModel::hold() {
  wake();
  motion_.profile_start = motion_.state_time;
  motion_.profile = Profile::hold(motion_.motor.state().position);
  motion_.step_profile = false;
  motion_.velocity_demand = 0;
  drive_->goal_to_present();
}

void MotionModel::republish() {
  publish();
}

void MotionModel::stop() {
  drive_->stop_goals();
  hold();
  protection_.report_bus_watchdog();
}

void MotionModel::clear_turns() {
  wake();
  motion_.wrap_to_one_turn();
  motion_.profile.reset();
  // A servo holding with torque on now holds at the wrapped position, not at the old goal.
  if (motion_.torque_on()) {
    hold();
  }
  publish();
}

void MotionModel::after_reboot() {
  // The table was just re-initialised: its Present values are not device-side changes.
  activity_ = Activity::Active;
  // includes/control_table_opmode_note.md: at power-on and reboot Present Position is within one
  // turn again (not for MX 1.0 multi-turn, whose position is absolute within its range).
  if (motion_.traits.one_turn_at_boot) {
    motion_.wrap_to_one_turn();
  }
  protection_.reset();
  motion_.profile.reset();
  motion_.velocity_demand = 0;
  publish();
  drive_->goal_to_present();
  if (motion_.torque_on()) {
    hold();  // Startup Configuration turned torque on
  }
}

void MotionModel::set_conditions(const Conditions& conditions) {
  motion_.conditions = conditions;
  wake();
}

void MotionModel::set_hand(std::shared_ptr<const Hand> hand) {
  hand_ = std::move(hand);
  wake();
}

void MotionModel::set_injected(FaultSet faults) {
  protection_.set_injected(faults);
  wake();
}

std::uint8_t MotionModel::v1_error_bits() const {
  return protection_.v1_error_bits();
}

// --- ticks ---------------------------------------------------------------------------------

void MotionModel::wake() {
  absorb_device_changes();
  activity_ = Activity::Active;
}

void MotionModel::absorb_device_changes() {
  // Present values set device-side (tests, the control API) move the physical state there.
  if (present_.absorb(*drive_)) {
    activity_ = Activity::Active;
  }
}

void MotionModel::advance_to(sim::SimTime now) {
  absorb_device_changes();
  if (coupling_) {
    // The world runs every coupled servo's ticks, this one's among them.
    coupling_->clock().advance_to(now);
    publish_realtime_tick(now);
    return;
  }
  while (next_tick_ <= now) {
    if (activity_ == Activity::Resting) {
      // Nothing changes until an input does: jump to the first tick after `now`.
      next_tick_ += ((now - next_tick_) / tick_ + 1) * tick_;
      motion_.state_time = next_tick_ - tick_;
      break;
    }
    if (activity_ == Activity::Cooling) {
      cool_until(now);
      break;
    }
    run_tick();
    next_tick_ += tick_;
  }
  publish_realtime_tick(now);
}

void MotionModel::publish_realtime_tick(sim::SimTime now) {
  if (motion_.items.realtime_tick) {
    motion_.table.set(
        *motion_.items.realtime_tick,
        std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() %
            kRealtimeTickWrap);
  }
}

void MotionModel::run_tick() {
  const MotorState before = motion_.motor.state();
  const bool was_running = motion_.profile_running();
  const double torque_share = motion_.protection_torque_share;
  motion_.state_time = next_tick_;
  const std::optional<Grip> grip = hand_ ? hand_->grip(next_tick_) : std::nullopt;
  motion_.motor.step(command(), motion_.conditions, grip ? &*grip : nullptr);
  protection_.check();
  publish();
  const MotorState& after = motion_.motor.state();
  MotorState same_heat = before;
  same_heat.temperature_c = after.temperature_c;
  // A protection that gave the motor its torque back (or took it) moves the shaft from the next
  // tick on, though this one changed nothing.
  const bool still = after == same_heat && !was_running && !after.at_limit &&
                     (drive_->mode() == Mode::Velocity || motion_.velocity_demand == 0) &&
                     motion_.protection_torque_share == torque_share &&
                     (!grip || hand_->still_from(next_tick_));
  if (!still) {
    activity_ = Activity::Active;
  } else if (after.temperature_c == before.temperature_c) {
    activity_ = Activity::Resting;
  } else {
    // Only the winding's temperature moves, and no current flows: cool_until() runs just that.
    activity_ = after.current_a == 0 ? Activity::Cooling : Activity::Active;
  }
}

void MotionModel::couple(physics::WorldClock& clock, const JointMapping& mapping) {
  coupling_ = std::make_unique<JointCoupling>(*this, clock, mapping);
  // The shaft is where the joint is; the servo starts there as at power-on.
  motion_.motor.set_position(coupling_->shaft_position());
  after_reboot();
}

double MotionModel::begin_coupled_tick(sim::SimTime tick_end) {
  absorb_device_changes();
  motion_.state_time = tick_end;
  next_tick_ = tick_end + tick_;
  return motion_.motor.drive(command(), motion_.conditions);
}

double MotionModel::coupled_hand_torque(sim::SimTime tick_end) const {
  const std::optional<Grip> grip = hand_ ? hand_->grip(tick_end) : std::nullopt;
  return grip ? motion_.motor.coupled_hand_torque(*grip) : 0.0;
}

void MotionModel::end_coupled_tick(double position, double velocity) {
  motion_.motor.follow_shaft(position, velocity, motion_.conditions);
  protection_.check();
  publish();
  // The world moves the shaft whatever the servo does: no tick is skipped.
  activity_ = Activity::Active;
}

void MotionModel::cool_until(sim::SimTime now) {
  // Equivalent to full ticks while the shaft is still and no current flows: each would only
  // step the temperature, whose relaxation is monotonic, so the errors it raises or clears are
  // those at the end (one check), and the Present values those at the end (publish() once).
  const auto ticks = (now - next_tick_) / tick_ + 1;
  bool settled = false;
  for (std::int64_t i = 0; i < ticks && !settled; ++i) {
    settled = motion_.motor.cool(motion_.conditions);
  }
  motion_.state_time = next_tick_ + (ticks - 1) * tick_;
  next_tick_ += ticks * tick_;
  protection_.check();
  publish();
  if (settled) {
    activity_ = Activity::Resting;
  }
}

DriveCommand MotionModel::command() {
  if (!motion_.torque_on()) {
    return {};
  }
  return drive_->command();
}

void MotionModel::publish() {
  drive_->publish();
  present_.publish();
}

}  // namespace dxlemu::model
