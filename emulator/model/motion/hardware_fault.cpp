#include "model/motion/hardware_fault.hpp"

namespace dxlemu::model {

std::uint8_t fault_bit(const FaultBits& bits, HardwareFault fault) {
  switch (fault) {
    case HardwareFault::InputVoltage:
      return bits.input_voltage;
    case HardwareFault::Overheating:
      return bits.overheating;
    case HardwareFault::Overload:
      return bits.overload;
    case HardwareFault::ElectricalShock:
      return bits.electrical_shock;
    case HardwareFault::Encoder:
      return bits.encoder;
    case HardwareFault::HallSensor:
      return bits.hall_sensor;
  }
  return 0;
}

std::uint8_t fault_bit(Family family, HardwareFault fault) {
  return fault_bit(traits_of(family).fault_bits, fault);
}

std::uint8_t fault_bits(Family family, FaultSet faults) {
  std::uint8_t bits = 0;
  for (const HardwareFault f : kHardwareFaults) {
    if ((faults & fault_set(f)) != 0) {
      bits |= fault_bit(family, f);
    }
  }
  return bits;
}

FaultSet faults_of(Family family, std::int64_t bits) {
  FaultSet faults = 0;
  for (const HardwareFault f : kHardwareFaults) {
    const std::uint8_t bit = fault_bit(family, f);
    if (bit != 0 && (bits & bit) != 0) {
      faults |= fault_set(f);
    }
  }
  return faults;
}

ErrorRule error_rule(const ErrorRules& rules, HardwareFault fault) {
  switch (fault) {
    case HardwareFault::InputVoltage:
      return rules.input_voltage;
    case HardwareFault::Overheating:
      return rules.overheating;
    case HardwareFault::Overload:
      return rules.overload;
    case HardwareFault::ElectricalShock:
      return rules.electrical_shock;
    case HardwareFault::Encoder:
      return rules.encoder;
    case HardwareFault::HallSensor:
      return rules.hall_sensor;
  }
  return {};
}

FaultSet faults_ending(const ErrorRules& rules, ErrorEnd end) {
  FaultSet faults = 0;
  for (const HardwareFault f : kHardwareFaults) {
    if (error_rule(rules, f).end == end) {
      faults |= fault_set(f);
    }
  }
  return faults;
}

std::string_view fault_name(HardwareFault fault) {
  switch (fault) {
    case HardwareFault::InputVoltage:
      return "input_voltage";
    case HardwareFault::Overheating:
      return "overheating";
    case HardwareFault::Overload:
      return "overload";
    case HardwareFault::ElectricalShock:
      return "electrical_shock";
    case HardwareFault::Encoder:
      return "encoder";
    case HardwareFault::HallSensor:
      return "hall_sensor";
  }
  return "";
}

std::optional<HardwareFault> fault_from_name(std::string_view name) {
  for (const HardwareFault f : kHardwareFaults) {
    if (fault_name(f) == name) {
      return f;
    }
  }
  return std::nullopt;
}

}  // namespace dxlemu::model
