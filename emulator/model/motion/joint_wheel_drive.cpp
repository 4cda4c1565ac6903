#include "model/motion/drive.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace dxlemu::model {
namespace {

// MX 1.0 Goal Acceleration unit: 8.583 °/s².
constexpr double kMx1AccelerationDegS2 = 8.583;
constexpr double kMsPerSecond = 1000;
// Compliance Slope's smallest representative value (includes/control_table_compliance_slope.md).
constexpr std::int64_t kMinComplianceSlope = 2;
// XL-320 Control Mode: 1 is wheel mode.
constexpr std::int64_t kXl320WheelMode = 1;

/// The drive of the Protocol 1.0 families and XL-320 (DriveKind::JointWheel): joint mode
/// follows Goal Position at Moving Speed (MX 1.0: with Goal Acceleration) within one turn, or
/// over turns in MX 1.0 multi-turn mode; wheel mode (both angle limits 0; XL-320: Control Mode
/// 1) turns at Moving Speed as output. Torque Limit caps the torque; AX, RX and EX yield within
/// their Compliance Margin and Slope. docs/motion.md "Protocol 1.0 families and XL-320".
class JointWheelDrive final : public Drive {
 public:
  explicit JointWheelDrive(MotionContext& motion) : motion_(motion) {}

  std::optional<Mode> mode() const override { return wheel_mode() ? Mode::Pwm : Mode::Position; }

  double torque_cap() const override {
    // Torque Limit: 0.1 % of the maximum torque.
    return motion_.motor.params().stall_torque_nm *
           static_cast<double>(motion_.get(motion_.items.torque_limit, kV1Magnitude)) /
           kV1Magnitude;
  }

  DriveCommand command() override {
    DriveCommand c;
    c.torque_cap_nm = torque_cap();
    if (wheel_mode()) {
      // Wheel mode: Moving Speed is output, 0.1 % of the maximum, bit 10 for CW.
      const std::int64_t speed = motion_.get(motion_.items.moving_speed);
      c.kind = DriveCommand::Kind::Pwm;
      c.duty = static_cast<double>(speed & kV1Magnitude) / kV1Magnitude *
               ((speed & kV1Cw) != 0 ? -1.0 : 1.0);
      return c;
    }
    c.kind = DriveCommand::Kind::Follow;
    if (motion_.profile) {
      const ProfilePoint point = motion_.profile->at(motion_.profile_elapsed_ms());
      c.target = point.position + compliance_offset();
      c.velocity = point.velocity;
    } else {
      c.target = motion_.motor.state().position;
    }
    return c;
  }

  void plan_to(double goal) override {
    // Moving Speed (0: as fast as the motor goes); MX 1.0 Goal Acceleration (0: no limit).
    double a = motion_.fastest_acceleration();
    if (const std::int64_t acc = motion_.get(motion_.items.goal_acceleration); acc > 0) {
      a = std::min(a, static_cast<double>(acc) * kMx1AccelerationDegS2 /
                          motion_.table.spec().motion.degrees_per_pulse /
                          (kMsPerSecond * kMsPerSecond));
    }
    motion_.plan_at_speed(goal, a);
  }

  double raw_goal(std::int64_t value) const override {
    const double raw = motion_.direction() * (static_cast<double>(value) - motion_.homing());
    if (motion_.multi_turn()) {
      return raw;
    }
    // Joint mode reads and commands positions within one turn: the goal is in the turn the shaft
    // is in now (after turns in wheel mode, too).
    const double turn = motion_.motor.params().pulses_per_rev;
    return std::floor(motion_.motor.state().position / turn) * turn + raw;
  }

  void goal_to_present() override {
    motion_.put(motion_.items.goal_position, motion_.present_position());
  }

  void stop_goals() override {}

  void publish() override {
    const MotorParams& p = motion_.motor.params();
    const MotorState& s = motion_.motor.state();
    const MotionItems& items = motion_.items;
    if (items.present_position) {
      const ItemSpec& item = motion_.table.spec().items[*items.present_position];
      double position = s.position;
      if (!motion_.multi_turn()) {
        // Joint and wheel mode read the position within one turn; past the item's range (the
        // 60° dead zone of AX/RX) it reads as the range's end, 1023 (docs/motion.md).
        position -= std::floor(position / p.pulses_per_rev) * p.pulses_per_rev;
      }
      std::int64_t value = round_to(position + motion_.homing());
      if (item.max > item.min) {
        value = std::clamp(value, item.min, item.max);
      }
      motion_.put(items.present_position, value);
    }
    const auto magnitude = [](double v) {
      const std::int64_t m = std::min(kV1Magnitude, round_to(std::abs(v)));
      return m | (m != 0 && v < 0 ? kV1Cw : 0);
    };
    motion_.put(items.present_speed, magnitude(s.velocity / p.velocity_unit));
    motion_.put(items.present_load, magnitude(s.torque_nm / p.stall_torque_nm * kV1Magnitude));
    if (p.current_unit_a) {
      // EX-106+ Sensed Current: 512 is 0 A, 10 mA per unit; MX 1.0 Current: 2048 is 0 A ("At an
      // idle state without current flow, this value is 2,048"), 4.5 mA per unit. Both from the
      // model file's motion block.
      const std::int64_t current = motion_.current_reading(s.current_a);
      motion_.put(items.sensed_current, current);
      motion_.put(items.current, current);
    }
    const bool running = motion_.profile_running() && motion_.torque_on();
    motion_.put(items.moving, running || round_to(s.velocity / p.velocity_unit) != 0 ? 1 : 0);
  }

 private:
  bool wheel_mode() const {
    // XL-320 Control Mode 1 is wheel mode; 1.0 models are in wheel mode with both angle limits 0
    // (includes/control_table_mx_angle_limit.md).
    const MotionItems& items = motion_.items;
    if (items.control_mode) {
      return motion_.get(items.control_mode) == kXl320WheelMode;
    }
    return items.cw_angle_limit && motion_.get(items.cw_angle_limit) == 0 &&
           motion_.get(items.ccw_angle_limit) == 0;
  }

  double compliance_offset() const {
    // AX, RX, EX (includes/control_table_compliance_slope.md): no torque within the Compliance
    // Margin, then torque rising over the Compliance Slope. Under an external load the shaft
    // settles where that torque meets the load: margin + slope × load / torque cap, on the side
    // the load pushes it (docs/motion.md).
    const MotionItems& items = motion_.items;
    const double load = motion_.conditions.external_load_nm;
    const double cap = torque_cap();
    if (!items.cw_compliance_margin || load == 0 || cap <= 0) {
      return 0;
    }
    const bool ccw = load > 0;
    const auto margin = static_cast<double>(
        motion_.get(ccw ? items.ccw_compliance_margin : items.cw_compliance_margin));
    const std::int64_t slope_data =
        motion_.get(ccw ? items.ccw_compliance_slope : items.cw_compliance_slope);
    // "Data representative value is actually used": the power of two at or below it, at least 2.
    std::int64_t slope = kMinComplianceSlope;
    while (slope * 2 <= slope_data) {
      slope *= 2;
    }
    return sign_of(load) *
           (margin + static_cast<double>(slope) * std::min(1.0, std::abs(load) / cap));
  }

  MotionContext& motion_;
};

}  // namespace

std::unique_ptr<Drive> joint_wheel_drive(MotionContext& motion) {
  return std::make_unique<JointWheelDrive>(motion);
}

}  // namespace dxlemu::model
