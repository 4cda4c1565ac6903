#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "model/motion/motion_context.hpp"
#include "model/motion/motor_physics.hpp"

namespace dxlemu::model {

/// The control modes the motion model knows, whatever items select them.
/// Step: FEETECH's step mode, where Goal Position is a number of steps to move from where the
/// shaft is, and Present Position the steps still to go.
enum class Mode { Current, Velocity, Position, Extended, CurrentPosition, Pwm, Step };

/// True for the modes that follow Goal Position.
inline bool is_position_mode(std::optional<Mode> mode) {
  return mode == Mode::Position || mode == Mode::Extended || mode == Mode::CurrentPosition ||
         mode == Mode::Step;
}

/// How a family's goal items select a control mode and move the motor, and how the motor shows
/// in its Present motion items (FamilyTraits::drive): one implementation per kind of control
/// table, working on the MotionContext it was made for. The motion model decides when; a drive
/// decides what the items mean.
class Drive {
 public:
  /// The drive of `motion`'s family, working on `motion`, which must outlive it.
  static std::unique_ptr<Drive> of(MotionContext& motion);

  virtual ~Drive() = default;
  Drive(const Drive&) = delete;
  Drive& operator=(const Drive&) = delete;

  /// The mode the items select now; nullopt when they select one the emulator does not model.
  virtual std::optional<Mode> mode() const = 0;
  /// The most torque the motor may give now, N·m.
  virtual double torque_cap() const = 0;
  /// What the motor does this tick, with torque on.
  virtual DriveCommand command() = 0;
  /// Starts a move from the motor's state to `goal` (a motor position, pulses).
  virtual void plan_to(double goal) = 0;
  /// The motor position, pulses, that a Goal Position (or a Present Position set device-side)
  /// of `value` stands for.
  virtual double raw_goal(std::int64_t value) const = 0;
  /// Goal Position takes the present position, where the goal could have been written.
  virtual void goal_to_present() = 0;
  /// Bus Watchdog expiry: the goals of the modes that do not follow a position go to 0.
  virtual void stop_goals() = 0;
  /// Writes the Present motion items (position, speed, load or current, PWM, trajectories,
  /// Moving, Moving Status) from the motor's state.
  virtual void publish() = 0;

 protected:
  Drive() = default;
};

/// The drive of the Protocol 1.0 families and XL-320 (DriveKind::JointWheel): joint and wheel
/// mode by the angle limits, Moving Speed, Torque Limit, Compliance (joint_wheel_drive.cpp).
std::unique_ptr<Drive> joint_wheel_drive(MotionContext& motion);

/// The drive of X, MX(2.0), P and PRO (DriveKind::OperatingMode): Operating Mode, profiles,
/// Drive Mode, current and PWM limits (operating_mode_drive.cpp).
std::unique_ptr<Drive> operating_mode_drive(MotionContext& motion);

}  // namespace dxlemu::model
