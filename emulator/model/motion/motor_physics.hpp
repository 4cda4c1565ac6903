#pragma once

#include <limits>

#include "model/motion/hand.hpp"
#include "model/spec/motor_params.hpp"

namespace dxlemu::model {

/// The world around one servo, set through the control API or by tests.
struct Conditions {
  double ambient_c = 25;
  double supply_v = 12;
  /// External torque on the output shaft, N·m; positive turns it towards higher positions.
  double external_load_nm = 0;
  /// The shaft cannot turn at all.
  bool blocked = false;
};

/// What the servo's controller asks of the motor for one tick.
struct DriveCommand {
  enum class Kind {
    Off,     ///< torque off: the shaft is free (it follows an external load)
    Follow,  ///< be at `target` at the end of the tick (position and velocity control)
    Torque,  ///< produce `torque_nm` (current control)
    Pwm,     ///< apply `duty` of the supply voltage (PWM control, 1.0 wheel mode)
  };
  Kind kind = Kind::Off;
  double target = 0;  ///< Follow: pulses
  /// Follow: the target's own velocity, pulses/ms (the feed-forward of a shaft coupled to a
  /// physics world; step() ignores it).
  double velocity = 0;
  double torque_nm = 0;  ///< Torque
  double duty = 0;       ///< Pwm: -1 ~ 1
  /// The most torque the controller may use by its limits (Current Limit, Torque Limit): at
  /// that, sustained, the motor is overloaded.
  double torque_cap_nm = std::numeric_limits<double>::infinity();
  /// The most torque the goal asks for (Goal Current in Current-based Position mode): the motor
  /// holds at that as long as asked, without overload.
  double goal_cap_nm = std::numeric_limits<double>::infinity();
  /// PWM Limit as a fraction of the supply: bounds speed in every mode.
  double duty_cap = 1;
};

/// The physical state of the motor and shaft after a tick.
struct MotorState {
  double position = 0;  ///< pulses, continuous over turns, before direction and Homing Offset
  double velocity = 0;  ///< pulses/ms
  double torque_nm = 0;
  double current_a = 0;
  double duty = 0;  ///< -1 ~ 1
  double temperature_c = 25;
  /// The motor gives all the torque its limits let it at standstill (blocked, overpowered, or
  /// asked for more): what sustained, raises Overload Error. Not at a goal's own cap
  /// (DriveCommand::goal_cap_nm).
  bool at_limit = false;

  bool operator==(const MotorState&) const = default;
};

/// A DC motor behind a gearbox with a linear torque-speed curve, a winding that heats with I²R
/// and cools towards ambient, and an external load. Steps of fixed length; deterministic.
/// docs/motion.md "The motor".
class MotorPhysics {
 public:
  /// A motor with `params`, ticking every `tick_ms`, its shaft at `position`.
  MotorPhysics(const MotorParams& params, double tick_ms, double position, double temperature_c);

  /// Advances one tick under `command` and the `outside` conditions, the shaft held by `grip` when
  /// it is not null (docs/hands.md): with torque off it is where the grip is at the end of the
  /// tick; with torque on the hand pushes it there with up to the grip's force, an external load
  /// the motor meets.
  void step(const DriveCommand& command, const Conditions& outside, const Grip* grip = nullptr);

  /// The torque a hand at `grip` puts on a shaft coupled to a physics world, N·m at the output:
  /// a spring as stiff as the servo's own position loop, damped as its back-EMF damps it, up to
  /// the grip's force.
  double coupled_hand_torque(const Grip& grip) const;

  /// A shaft coupled to a physics world (docs/physics.md), first half of a tick: the torque the
  /// motor puts on its shaft for the tick under `command`, from the shaft's state at its start.
  /// The controller's output is a duty; the duty of the supply, less the back-EMF of the shaft's
  /// speed, drives current through the winding, and the current makes torque. Sets torque,
  /// current, duty and at_limit; the external load and `blocked` of `conditions` are the
  /// world's business. N·m at the output shaft.
  double drive(const DriveCommand& command, const Conditions& conditions);
  /// Second half: the shaft is where the world moved it (pulses, pulses/ms); the winding heats.
  void follow_shaft(double position, double velocity, const Conditions& conditions);

  const MotorState& state() const { return state_; }
  /// Device side: moves the shaft without dynamics (Clear, position reset to one turn).
  void set_position(double position) { state_.position = position; }
  /// One tick of the thermal model alone: what step() does to a still shaft with no current.
  /// Returns true once the temperature has reached its steady value (further ticks change
  /// nothing).
  bool cool(const Conditions& conditions);
  /// Device side: sets the winding temperature.
  void set_temperature(double celsius) { state_.temperature_c = celsius; }
  const MotorParams& params() const { return params_; }
  double tick_ms() const { return tick_ms_; }
  /// The fastest the shaft turns with `duty_cap` of `supply_v`, pulses/ms.
  double top_speed(double duty_cap, double supply_v) const;

 private:
  double follow(const DriveCommand& command, const Conditions& conditions, double& torque);
  double accelerate(double torque, double cap, const Conditions& conditions, double top) const;
  double free_velocity(const Conditions& conditions) const;
  double available(double direction, double cap, double supply, double duty_cap) const;
  void heat(const Conditions& conditions);
  /// `grip`'s position on the turn nearest the shaft, pulses.
  double nearest_turn(const Grip& grip) const;
  /// The torque that lands a free shaft on `grip` at the end of this tick, within its force.
  double hand_torque(const Grip& grip) const;

  MotorParams params_;
  double tick_ms_;
  double cooling_;  // exp(-tick / thermal time): the share of a temperature difference left
  MotorState state_;
};

}  // namespace dxlemu::model
