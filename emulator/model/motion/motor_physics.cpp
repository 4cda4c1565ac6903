#include "model/motion/motor_physics.hpp"

#include <algorithm>
#include <cmath>

#include "model/motion/signum.hpp"

namespace dxlemu::model {
namespace {

// A free (torque off) shaft resists this share of stall torque before an external load turns
// it: gearbox friction and detent.
constexpr double kFreeFriction = 0.05;
// A blocked or lagging shaft: the position controller reaches full torque at this error
// (pulses per revolution share), like a stiff P gain.
constexpr double kFullTorqueErrorRev = 1.0 / 64;
// At or above this share of the available standstill torque the motor counts as at its limit.
constexpr double kAtLimit = 0.95;
// A temperature this close to its steady value, and a speed this close to 0 (pulses/ms), are
// taken as there: decays end, so a servo comes to rest exactly.
constexpr double kTemperatureSnapC = 1e-3;
constexpr double kVelocitySnap = 1e-6;

}  // namespace

MotorPhysics::MotorPhysics(const MotorParams& params, double tick_ms, double position,
                           double temperature_c)
    : params_(params), tick_ms_(tick_ms), cooling_(std::exp(-tick_ms / params.thermal_time_ms)) {
  state_.position = position;
  state_.temperature_c = temperature_c;
}

double MotorPhysics::top_speed(double duty_cap, double supply_v) const {
  return params_.no_load_speed * std::max(0.0, duty_cap) * std::max(0.0, supply_v) /
         params_.nominal_voltage_v;
}

double MotorPhysics::free_velocity(const Conditions& conditions) const {
  // A load above the gearbox's friction back-drives the shaft at a speed that grows with it.
  const double friction = kFreeFriction * params_.stall_torque_nm;
  const double excess = std::abs(conditions.external_load_nm) - friction;
  if (conditions.blocked || excess <= 0) {
    return 0;
  }
  return signum(conditions.external_load_nm) * params_.no_load_speed *
         std::min(1.0, excess / params_.stall_torque_nm);
}

double MotorPhysics::accelerate(double torque, double cap, const Conditions& conditions,
                                double top) const {
  const double net = std::clamp(torque, -cap, cap) + conditions.external_load_nm;
  const double v = state_.velocity + net / params_.inertia * tick_ms_;
  return std::clamp(v, -top, top);
}

double MotorPhysics::available(double direction, double cap, double supply, double duty_cap) const {
  // Braking (torque against the motion) gets the whole cap; driving loses torque to back-EMF as
  // speed grows (linear torque-speed curve), none left at the no-load speed of the duty.
  const double v = state_.velocity;
  if (direction * v <= 0) {
    return cap;
  }
  const double drive =
      params_.stall_torque_nm * (std::max(0.0, duty_cap) * supply / params_.nominal_voltage_v -
                                 std::abs(v) / params_.no_load_speed);
  return std::clamp(drive, 0.0, cap);
}

double MotorPhysics::follow(const DriveCommand& command, const Conditions& conditions,
                            double& torque) {
  const double supply = std::max(0.0, conditions.supply_v);
  const double top = top_speed(command.duty_cap, supply);
  const double cap = command.torque_cap_nm;
  const double wanted = (command.target - state_.position) / tick_ms_;
  if (conditions.blocked) {
    const double error = command.target - state_.position;
    torque =
        std::clamp(params_.stall_torque_nm * error / (kFullTorqueErrorRev * params_.pulses_per_rev),
                   -cap, cap);
    return 0;
  }
  // The torque to be exactly on target at the end of the tick, against the external load.
  const double needed =
      params_.inertia * (wanted - state_.velocity) / tick_ms_ - conditions.external_load_nm;
  const double avail = available(signum(needed), cap, supply, command.duty_cap);
  if (std::abs(needed) <= avail && std::abs(wanted) <= top) {
    torque = needed;
    return wanted;
  }
  torque = std::clamp(needed, -avail, avail);
  double v = accelerate(torque, avail, conditions, top);
  // The controller never drives past its target within a tick.
  if (signum(v) == signum(wanted) && std::abs(v) > std::abs(wanted)) {
    v = wanted;
  }
  return v;
}

double MotorPhysics::nearest_turn(const Grip& grip) const {
  const double turn = params_.pulses_per_rev;
  return grip.position + std::round((state_.position - grip.position) / turn) * turn;
}

double MotorPhysics::hand_torque(const Grip& grip) const {
  // A hand is stiffer than anything a tick can resolve: it pushes with what it takes to have the
  // free shaft on its position at the end of the tick, as far as its force goes.
  const double wanted = (nearest_turn(grip) - state_.position) / tick_ms_;
  const double needed = params_.inertia * (wanted - state_.velocity) / tick_ms_;
  return std::clamp(needed, -grip.force_limit_nm, grip.force_limit_nm);
}

double MotorPhysics::coupled_hand_torque(const Grip& grip) const {
  // The world integrates a joint whose inertia the servo does not know: a spring no stiffer than
  // the servo's own position loop (stable there by construction), with its back-EMF's damping.
  const double stiffness = params_.stall_torque_nm / (kFullTorqueErrorRev * params_.pulses_per_rev);
  const double damping = params_.stall_torque_nm / params_.no_load_speed;
  const double torque = stiffness * (nearest_turn(grip) - state_.position) +
                        damping * (grip.velocity - state_.velocity);
  return std::clamp(torque, -grip.force_limit_nm, grip.force_limit_nm);
}

void MotorPhysics::step(const DriveCommand& command, const Conditions& outside, const Grip* grip) {
  // A hand is one more external load, unless the motor gives no torque (below).
  Conditions conditions = outside;
  if (grip != nullptr) {
    conditions.external_load_nm += hand_torque(*grip);
  }
  const double supply = std::max(0.0, conditions.supply_v);
  // What the motor can give at standstill: the supply over the winding, and the controller's cap.
  const double stall_at_supply = params_.stall_torque_nm * supply / params_.nominal_voltage_v;
  // What the limits leave the motor; the goal's own cap (Goal Current) may ask for less.
  const double limit =
      std::min(command.torque_cap_nm, stall_at_supply * std::max(0.0, command.duty_cap));
  double cap = std::min(limit, command.goal_cap_nm);
  DriveCommand limited = command;
  limited.torque_cap_nm = cap;
  double torque = 0;
  double velocity = 0;
  // A controller with no torque to give (Torque Limit 0 after Alarm Shutdown, Goal Current 0)
  // leaves the shaft as free as torque off does.
  const DriveCommand::Kind kind = cap > 0 ? command.kind : DriveCommand::Kind::Off;
  switch (kind) {
    case DriveCommand::Kind::Off:
      cap = 0;
      if (grip != nullptr && !conditions.blocked) {
        // A free shaft goes where the hand takes it (a leader arm moved by hand): its friction
        // is far below any hand's force.
        velocity = (nearest_turn(*grip) - state_.position) / tick_ms_;
      } else {
        velocity = free_velocity(conditions);
      }
      break;
    case DriveCommand::Kind::Follow:
      velocity = follow(limited, conditions, torque);
      break;
    case DriveCommand::Kind::Torque: {
      const double avail = available(signum(command.torque_nm), cap, supply, command.duty_cap);
      torque = std::clamp(command.torque_nm, -avail, avail);
      velocity = conditions.blocked
                     ? 0
                     : accelerate(torque, cap, conditions, top_speed(command.duty_cap, supply));
      break;
    }
    case DriveCommand::Kind::Pwm: {
      // Linear torque-speed curve at the applied duty: no torque at that duty's no-load speed.
      const double duty = std::clamp(command.duty, -command.duty_cap, command.duty_cap);
      torque = params_.stall_torque_nm * (duty * supply / params_.nominal_voltage_v -
                                          state_.velocity / params_.no_load_speed);
      torque = std::clamp(torque, -cap, cap);
      velocity = conditions.blocked
                     ? 0
                     : accelerate(torque, cap, conditions, top_speed(command.duty_cap, supply));
      break;
    }
  }
  torque = std::clamp(torque, -cap, cap);
  if (std::abs(velocity) < kVelocitySnap) {
    velocity = 0;
  }
  state_.at_limit = cap > 0 && std::abs(torque) >= kAtLimit * limit;
  state_.velocity = velocity;
  state_.position += velocity * tick_ms_;
  state_.torque_nm = torque;
  state_.current_a = torque / params_.torque_constant();
  // Duty: the winding's IR drop plus the back-EMF, over the supply.
  state_.duty =
      supply > 0
          ? std::clamp(
                params_.nominal_voltage_v / supply *
                    (state_.current_a / params_.stall_current_a +
                     (kind == DriveCommand::Kind::Off ? 0.0 : velocity / params_.no_load_speed)),
                -1.0, 1.0)
          : 0.0;
  heat(conditions);
}

double MotorPhysics::drive(const DriveCommand& command, const Conditions& conditions) {
  const double supply = std::max(0.0, conditions.supply_v);
  const double stall_at_supply = params_.stall_torque_nm * supply / params_.nominal_voltage_v;
  const double duty_cap = std::clamp(command.duty_cap, 0.0, 1.0);
  const double limit = std::min(command.torque_cap_nm, stall_at_supply * duty_cap);
  const double cap = std::min(limit, command.goal_cap_nm);
  const DriveCommand::Kind kind = cap > 0 ? command.kind : DriveCommand::Kind::Off;
  const double v = state_.velocity;
  // Duty per share of the nominal voltage: 1 at the nominal supply.
  const double per_nominal = supply > 0 ? params_.nominal_voltage_v / supply : 0.0;
  double duty = 0;
  switch (kind) {
    case DriveCommand::Kind::Off:
      break;
    case DriveCommand::Kind::Follow: {
      // A stiff P controller on the position error (full torque at kFullTorqueErrorRev) with
      // the target's velocity fed forward; the back-EMF of the difference in speed damps it.
      const double gain = params_.stall_torque_nm / (kFullTorqueErrorRev * params_.pulses_per_rev);
      const double wanted = gain * (command.target - state_.position);
      duty = per_nominal *
             (wanted / params_.stall_torque_nm + command.velocity / params_.no_load_speed);
      break;
    }
    case DriveCommand::Kind::Torque:
      // The duty whose current, after the back-EMF of the present speed, is the one asked for.
      duty =
          per_nominal * (command.torque_nm / params_.stall_torque_nm + v / params_.no_load_speed);
      break;
    case DriveCommand::Kind::Pwm:
      duty = command.duty;
      break;
  }
  duty = kind == DriveCommand::Kind::Off ? 0.0 : std::clamp(duty, -duty_cap, duty_cap);
  // PWM -> voltage -> current -> torque. Torque off leaves the winding open: no current.
  double current = 0;
  if (kind != DriveCommand::Kind::Off) {
    const double back_emf = params_.nominal_voltage_v * v / params_.no_load_speed;
    current = (duty * supply - back_emf) / params_.resistance();
  }
  const double torque =
      std::clamp(current * params_.torque_constant(), -std::max(0.0, cap), std::max(0.0, cap));
  state_.torque_nm = torque;
  state_.current_a = torque / params_.torque_constant();
  state_.duty = duty;
  state_.at_limit = kind != DriveCommand::Kind::Off && std::abs(torque) >= kAtLimit * limit;
  return torque;
}

void MotorPhysics::follow_shaft(double position, double velocity, const Conditions& conditions) {
  state_.position = position;
  state_.velocity = velocity;
  heat(conditions);
}

bool MotorPhysics::cool(const Conditions& conditions) {
  const double before = state_.temperature_c;
  heat(conditions);
  return state_.temperature_c == before;
}

void MotorPhysics::heat(const Conditions& conditions) {
  // First-order thermal model, stepped exactly: T relaxes towards ambient + P·Rth.
  const double power = state_.current_a * state_.current_a * params_.resistance();
  const double steady = conditions.ambient_c + power * params_.thermal_resistance;
  const double t = steady + (state_.temperature_c - steady) * cooling_;
  state_.temperature_c = std::abs(t - steady) < kTemperatureSnapC ? steady : t;
}

}  // namespace dxlemu::model
