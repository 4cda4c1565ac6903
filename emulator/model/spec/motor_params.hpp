#pragma once

#include <optional>

#include "model/spec/model_spec.hpp"

namespace dxlemu::model {

/// The physical figures of one model's motor and gearbox, in the motion model's units: position
/// in pulses, time in milliseconds, torque in N·m, current in A, voltage in V, temperature in °C.
/// Taken from the model file's `motion` object; where a model file states no figure, the default
/// documented in docs/motion.md is used.
struct MotorParams {
  double pulses_per_rev = 4096;
  /// Pulses per millisecond for one unit of the model's velocity items.
  double velocity_unit = 0;
  /// Pulses per ms² for one unit of Profile Acceleration, when the model has that item in
  /// rev/min².
  std::optional<double> acceleration_unit;
  /// Amperes for one unit of the model's current items, when it has them.
  std::optional<double> current_unit_a;
  double nominal_voltage_v = 12;
  /// No-load speed at the nominal voltage, pulses/ms.
  double no_load_speed = 0;
  double stall_torque_nm = 0;
  double stall_current_a = 0;
  /// Rotor and gear inertia seen at the output, N·m per (pulse/ms²): stall torque brings the
  /// shaft to no-load speed in kMechanicalTimeMs.
  double inertia = 0;
  /// Winding heating: °C per W above ambient, and the thermal time constant in ms.
  double thermal_resistance = 0;
  double thermal_time_ms = 0;
  /// How long the motor may stay at its torque limit before Overload Error, ms.
  double overload_ms = 0;

  /// Torque per ampere.
  double torque_constant() const { return stall_torque_nm / stall_current_a; }
  /// Winding resistance, Ω.
  double resistance() const { return nominal_voltage_v / stall_current_a; }

  /// The parameters of `spec`.
  static MotorParams of(const ModelSpec& spec);
};

}  // namespace dxlemu::model
