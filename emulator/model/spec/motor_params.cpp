#include "model/spec/motor_params.hpp"

namespace dxlemu::model {
namespace {

// Defaults for figures a model file does not state (docs/motion.md "Parameters").
constexpr double kDefaultNoLoadRpm = 60;
constexpr double kDefaultStallTorqueNm = 1.5;
constexpr double kDefaultStallCurrentA = 1.5;
constexpr double kDefaultVoltageV = 12;
// Time for stall torque to bring the unloaded shaft to no-load speed: sets the inertia.
constexpr double kMechanicalTimeMs = 20;
// Steady temperature rise with stall current flowing continuously, and how fast it is reached:
// chosen so that a blocked shaft overheats in about a minute, as servos at stall do.
constexpr double kStallRiseC = 120;
constexpr double kThermalTimeMs = 120'000;
// Load held at the limit this long raises Overload Error.
constexpr double kOverloadMs = 1'000;

constexpr double kMsPerMinute = 60'000;
constexpr double kDegreesPerRev = 360;
constexpr double kMilli = 1e-3;
// The power-on value of the input-voltage item, in volts: the supply a model file assumes.
std::optional<double> initial_voltage(const ModelSpec& spec) {
  for (const char* key : {"present_input_voltage", "present_voltage"}) {
    if (const ItemSpec* item = spec.find(key)) {
      return static_cast<double>(item->initial) *
             unit_figure(item->unit).value_or(kDefaultVoltageUnitV);
    }
  }
  return std::nullopt;
}

}  // namespace

MotorParams MotorParams::of(const ModelSpec& spec) {
  const MotionSpec& m = spec.motion;
  MotorParams p;
  p.pulses_per_rev = kDegreesPerRev / m.degrees_per_pulse;
  p.velocity_unit = m.velocity_unit_rpm * p.pulses_per_rev / kMsPerMinute;
  if (m.acceleration_unit_rpm2) {
    p.acceleration_unit =
        *m.acceleration_unit_rpm2 * p.pulses_per_rev / (kMsPerMinute * kMsPerMinute);
  }
  if (m.current_unit_ma) {
    p.current_unit_a = *m.current_unit_ma * kMilli;
  }
  p.nominal_voltage_v =
      m.nominal_voltage_v.value_or(initial_voltage(spec).value_or(kDefaultVoltageV));
  p.no_load_speed =
      m.no_load_speed_rpm.value_or(kDefaultNoLoadRpm) * p.pulses_per_rev / kMsPerMinute;
  p.stall_torque_nm = m.stall_torque_nm.value_or(kDefaultStallTorqueNm);
  p.stall_current_a = m.stall_current_a.value_or(kDefaultStallCurrentA);
  p.inertia = p.stall_torque_nm * kMechanicalTimeMs / p.no_load_speed;
  p.thermal_resistance = kStallRiseC / (p.nominal_voltage_v * p.stall_current_a);
  p.thermal_time_ms = kThermalTimeMs;
  p.overload_ms = kOverloadMs;
  return p;
}

}  // namespace dxlemu::model
