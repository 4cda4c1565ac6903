#include "model/motion/drive.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace dxlemu::model {
namespace {

// Moving Status bits (includes/control_table_moving_status.md).
constexpr std::int64_t kInPosition = 0x01;
constexpr std::int64_t kProfileOngoing = 0x02;
constexpr std::int64_t kFollowingError = 0x08;
// DYNAMIXEL-Y adds kMovingStatusMoving and kMovingStatusInRange (motion_context.hpp).

// In position: within this share of a turn of Goal Position once the profile is over. Following
// error: further than this share of a turn from the trajectory (docs/motion.md: chosen).
constexpr double kInPositionRev = 1.0 / 1024;
constexpr double kFollowingErrorRev = 1.0 / 36;

// Present Load of MX(2.0) without a current sensor: 0.1 % of the maximum torque.
constexpr double kLoadFullScale = 1000;

/// The drive of X, MX(2.0), P and PRO (DriveKind::OperatingMode): Operating Mode selects
/// current, velocity, position, extended position, current-based position or PWM control;
/// Profile Velocity and Profile Acceleration shape moves (velocity- or time-based by Drive Mode;
/// PRO: Goal Velocity, no profile); Current Limit, Goal Current and PWM Limit cap the motor.
/// docs/motion.md "Profiles" and "Operating modes".
class OperatingModeDrive final : public Drive {
 public:
  explicit OperatingModeDrive(MotionContext& motion) : motion_(motion) {}

  std::optional<Mode> mode() const override {
    // The family's Operating Mode values (FamilyTraits::operating_modes).
    const std::int64_t value = motion_.get(motion_.items.operating_mode);
    const OperatingModeValues& v = motion_.traits.operating_modes;
    const std::pair<std::optional<std::int64_t>, Mode> modes[] = {
        {v.current, Mode::Current},
        {v.velocity, Mode::Velocity},
        {v.position, Mode::Position},
        {v.extended, Mode::Extended},
        {v.current_position, Mode::CurrentPosition},
        {v.pwm, Mode::Pwm},
        {v.step, Mode::Step}};
    for (const auto& [mode_value, mode] : modes) {
      if (mode_value == value) {
        return mode;
      }
    }
    return std::nullopt;
  }

  double torque_cap() const override {
    const MotorParams& p = motion_.motor.params();
    const MotionItems& items = motion_.items;
    double cap = std::numeric_limits<double>::infinity();
    if (items.current_limit && p.current_unit_a) {
      cap = static_cast<double>(motion_.get(items.current_limit)) * *p.current_unit_a *
            p.torque_constant();
    }
    if (motion_.traits.torque_limit_caps_torque && items.torque_limit) {
      cap = std::min(cap, static_cast<double>(motion_.get(items.torque_limit)) / kLoadFullScale *
                              p.stall_torque_nm);
    }
    if (motion_.protection_torque_share < 1) {
      cap = std::min(cap, motion_.protection_torque_share * p.stall_torque_nm);
    }
    return cap;
  }

  // Current-based Position Control Mode: Goal Current bounds the torque as the goal asks, which
  // the servo holds as long as it is asked to (a gripper squeezing), unlike a limit.
  double goal_cap() const {
    const MotorParams& p = motion_.motor.params();
    const MotionItems& items = motion_.items;
    if (mode() == Mode::CurrentPosition && items.goal_current && p.current_unit_a) {
      return std::abs(static_cast<double>(motion_.get(items.goal_current))) * *p.current_unit_a *
             p.torque_constant();
    }
    return std::numeric_limits<double>::infinity();
  }

  DriveCommand command() override {
    DriveCommand c;
    c.torque_cap_nm = torque_cap();
    c.goal_cap_nm = goal_cap();
    c.duty_cap = motion_.duty_cap();
    const MotorParams& p = motion_.motor.params();
    const MotionItems& items = motion_.items;
    const auto m = mode();
    if (!m) {
      return {};
    }
    switch (*m) {
      case Mode::Current: {
        c.kind = DriveCommand::Kind::Torque;
        const double units =
            static_cast<double>(motion_.get(items.goal_current, motion_.get(items.goal_torque)));
        c.torque_nm =
            motion_.direction() * units * p.current_unit_a.value_or(0) * p.torque_constant();
        return c;
      }
      case Mode::Pwm: {
        c.kind = DriveCommand::Kind::Pwm;
        // Full duty: PWM Limit's top; FEETECH has no PWM Limit: its goal item's top (1000).
        const auto& top = items.pwm_limit ? items.pwm_limit : items.goal_pwm;
        const double full = top ? static_cast<double>(motion_.table.spec().items[*top].max) : 1.0;
        c.duty = motion_.direction() * static_cast<double>(motion_.get(items.goal_pwm)) / full;
        return c;
      }
      case Mode::Velocity: {
        const double goal = motion_.direction() *
                            static_cast<double>(motion_.get(items.goal_velocity)) * p.velocity_unit;
        c.kind = DriveCommand::Kind::Follow;
        c.velocity = ramp_velocity(goal);
        c.target = motion_.motor.state().position + c.velocity * motion_.motor.tick_ms();
        return c;
      }
      case Mode::Position:
      case Mode::Extended:
      case Mode::CurrentPosition:
      case Mode::Step:
        c.kind = DriveCommand::Kind::Follow;
        if (motion_.profile) {
          const ProfilePoint point = motion_.profile->at(motion_.profile_elapsed_ms());
          c.target = point.position;
          c.velocity = point.velocity;
        } else {
          c.target = motion_.motor.state().position;
        }
        return c;
    }
    return {};
  }

  void plan_to(double goal) override {
    const MotorParams& p = motion_.motor.params();
    const MotorState& s = motion_.motor.state();
    const MotionItems& items = motion_.items;
    if (!items.profile_velocity) {
      // PRO: Goal Velocity and no profile.
      motion_.plan_at_speed(goal, motion_.fastest_acceleration());
      return;
    }
    const bool time_based = (motion_.get(items.drive_mode) & kDriveModeTimeBased) != 0;
    auto velocity = static_cast<double>(motion_.get(items.profile_velocity));
    auto acceleration = static_cast<double>(motion_.get(items.profile_acceleration));
    if (time_based && items.profile_time) {
      // DYNAMIXEL-Y: "a time-based profile is created using Profile Acceleration Time(248) and
      // Profile Time(252)"; Profile Time 0 deactivates the profile.
      velocity = time_ms(items.profile_time);
      acceleration = time_ms(items.profile_acceleration_time);
    }
    if (velocity == 0) {
      // No profile: the motor goes as fast as it can (Moving Status reports no profile). The
      // desired position goes on from where it was, not from the shaft: without a profile the
      // goal is the desired position at once (the e-Manual's step), so a new goal never takes
      // back the position error a servo holds a load with. Planned from the shaft, every goal
      // written dropped that error, and the torque with it, for the few ms the motor takes to
      // build it up again: a joint under gravity, its goal rewritten every 10 ms as a
      // teleoperation loop does, sagged tens of degrees (tests/e2e/hands_test.py).
      const ProfilePoint from = motion_.desired_point();
      const double top = motion_.motor.top_speed(motion_.duty_cap(), motion_.conditions.supply_v);
      motion_.profile_start = motion_.state_time;
      motion_.profile = Profile::velocity_based(from.position, from.velocity, goal, top,
                                                motion_.fastest_acceleration());
      motion_.step_profile = true;
      return;
    }
    motion_.profile_start = motion_.state_time;
    motion_.step_profile = false;
    if (time_based) {
      motion_.profile = Profile::time_based(s.position, s.velocity, goal, velocity, acceleration);
      return;
    }
    const double a = acceleration == 0 || !p.acceleration_unit
                         ? std::numeric_limits<double>::infinity()
                         : acceleration * *p.acceleration_unit;
    motion_.profile =
        Profile::velocity_based(s.position, s.velocity, goal, velocity * p.velocity_unit, a);
  }

  double raw_goal(std::int64_t value) const override {
    // Present Position = direction · actual + Homing Offset.
    return motion_.direction() * (static_cast<double>(value) - motion_.homing());
  }

  void goal_to_present() override {
    const auto& goal_item = motion_.items.goal_position;
    if (!goal_item) {
      return;
    }
    // Only where the goal could have been written: within the position limits in Position mode.
    const auto m = mode();
    if (m == Mode::Step) {
      return;  // Goal Position is a step count there, not a place
    }
    const ItemSpec& goal = motion_.table.spec().items[*goal_item];
    const std::int64_t present = motion_.present_position();
    if (goal.in_range(present) || m == Mode::Extended || m == Mode::CurrentPosition) {
      motion_.put(goal_item, present);
    }
  }

  void stop_goals() override {
    // Current and PWM Control Mode stop too: their goal goes to 0.
    if (mode() == Mode::Current) {
      motion_.put(motion_.items.goal_current, 0);
    } else if (mode() == Mode::Pwm) {
      motion_.put(motion_.items.goal_pwm, 0);
    }
  }

  void publish() override {
    const MotorParams& p = motion_.motor.params();
    const MotorState& s = motion_.motor.state();
    const MotionItems& items = motion_.items;
    const double dir = motion_.direction();
    motion_.put(items.present_position, present_position());
    const std::int64_t velocity = round_to(dir * s.velocity / p.velocity_unit);
    motion_.put(items.present_velocity, velocity);
    motion_.put(items.present_speed, velocity);  // FEETECH's Present speed
    if (p.current_unit_a) {
      motion_.put(items.present_current, motion_.current_reading(dir * s.current_a));
    }
    // MX(2.0) without a current sensor, and FEETECH beside its current: 0.1 % of full torque.
    if (!p.current_unit_a || items.present_current) {
      motion_.put(items.present_load,
                  round_to(dir * s.torque_nm / p.stall_torque_nm * kLoadFullScale));
    }
    if (items.pwm_limit) {
      const auto full = static_cast<double>(motion_.table.spec().items[*items.pwm_limit].max);
      motion_.put(items.present_pwm, round_to(dir * s.duty * full));
    }
    const bool torque_on = motion_.torque_on();
    const bool running = motion_.profile_running() && torque_on;
    const bool positional = is_position_mode(mode()) && torque_on;
    if (positional && motion_.profile && mode() != Mode::Step) {
      const ProfilePoint point = motion_.profile->at(motion_.profile_elapsed_ms());
      motion_.put(items.position_trajectory, round_to(dir * point.position + motion_.homing()));
      motion_.put(items.velocity_trajectory, round_to(dir * point.velocity / p.velocity_unit));
    } else if (mode() == Mode::Velocity && torque_on) {
      motion_.put(items.velocity_trajectory,
                  round_to(dir * motion_.velocity_demand / p.velocity_unit));
    }
    // includes/control_table_moving_2.md: Moving when |Present Velocity| > Moving Threshold, or
    // while a profile runs.
    const bool moving = running || std::abs(velocity) > motion_.get(items.moving_threshold);
    motion_.put(items.moving, moving ? 1 : 0);
    publish_moving_status(running, positional, moving);
  }

 private:
  /// Present Position: where the shaft is; in FEETECH step mode "the step difference between
  /// the present position and the goal position", the steps still to go (docs/feetech.md).
  std::int64_t present_position() const {
    if (mode() != Mode::Step) {
      return motion_.present_position();
    }
    const double position = motion_.motor.state().position;
    const double goal = motion_.profile ? motion_.profile->goal() : position;
    return round_to(motion_.direction() * (goal - position));
  }

  /// A time item (DYNAMIXEL-Y Profile Time / Profile Acceleration Time) in milliseconds.
  double time_ms(const std::optional<std::size_t>& item) const {
    return static_cast<double>(motion_.get(item)) * motion_.items.profile_time_unit_ms;
  }

  double ramp_velocity(double goal) {
    // Velocity Control Mode ramps towards Goal Velocity with Profile Acceleration (0: a
    // step); time-based: Profile Acceleration is the time to reach it
    // (includes/control_table_profile_velocity.md, NOTE on Velocity Control Mode).
    const MotorParams& p = motion_.motor.params();
    double& demand = motion_.velocity_demand;
    const bool time_based = (motion_.get(motion_.items.drive_mode) & kDriveModeTimeBased) != 0;
    // DYNAMIXEL-Y: Profile Acceleration Time(248) is the time-based ramp, in Velocity Control too.
    const double acc = time_based && motion_.items.profile_acceleration_time
                           ? time_ms(motion_.items.profile_acceleration_time)
                           : static_cast<double>(motion_.get(motion_.items.profile_acceleration));
    double rate = std::numeric_limits<double>::infinity();
    if (acc > 0 && time_based) {
      // A change of Goal Velocity takes Profile Acceleration ms: the rate is set when the goal
      // changes, from the velocity the ramp had then.
      if (goal != ramp_goal_) {
        ramp_goal_ = goal;
        ramp_rate_ = std::abs(goal - demand) / acc;
      }
      rate = ramp_rate_;
    } else if (acc > 0 && p.acceleration_unit) {
      rate = acc * *p.acceleration_unit;
    }
    const double step = rate * motion_.motor.tick_ms();
    const double diff = goal - demand;
    demand = std::abs(diff) <= step ? goal : demand + sign_of(diff) * step;
    return demand;
  }

  void publish_moving_status(bool running, bool positional, bool moving) {
    const MotionItems& items = motion_.items;
    if (!items.moving_status) {
      return;
    }
    std::int64_t status = 0;
    if (motion_.traits.moving_status_motion_and_range) {
      // Moving: "Whether the device is rotating"; Position In Range: Present Position within
      // Min/Max Position Limit, in every mode.
      const std::int64_t position = motion_.get(items.present_position);
      const bool in_range = !items.min_position_limit || !items.max_position_limit ||
                            (position >= motion_.get(items.min_position_limit) &&
                             position <= motion_.get(items.max_position_limit));
      status |= (moving ? kMovingStatusMoving : 0) | (in_range ? kMovingStatusInRange : 0);
    }
    const auto& profile = motion_.profile;
    if (positional && profile) {
      if (!motion_.step_profile) {
        status |= static_cast<std::int64_t>(profile->type());
      }
      if (running) {
        status |= kProfileOngoing;
      }
      const double turn = motion_.motor.params().pulses_per_rev;
      const double position = motion_.motor.state().position;
      const ProfilePoint point = profile->at(motion_.profile_elapsed_ms());
      if (std::abs(point.position - position) > kFollowingErrorRev * turn) {
        status |= kFollowingError;
      }
      if (!running && std::abs(profile->goal() - position) <= kInPositionRev * turn) {
        status |= kInPosition;
      }
    }
    motion_.put(motion_.items.moving_status, status);
  }

  MotionContext& motion_;
  double ramp_goal_ = 0;  // time-based velocity mode: the goal the ramp rate is for
  double ramp_rate_ = 0;  // pulses/ms², set when that goal changed
};

}  // namespace

std::unique_ptr<Drive> operating_mode_drive(MotionContext& motion) {
  return std::make_unique<OperatingModeDrive>(motion);
}

}  // namespace dxlemu::model
