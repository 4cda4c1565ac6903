#include "model/hardware_fault.hpp"

#include <array>

namespace dxlemu::model {
namespace {

constexpr std::array<HardwareFault, 6> kFaults = {
    HardwareFault::InputVoltage,    HardwareFault::Overheating, HardwareFault::Overload,
    HardwareFault::ElectricalShock, HardwareFault::Encoder,     HardwareFault::HallSensor};

}  // namespace

std::uint8_t fault_bit(Family family, HardwareFault fault) {
  switch (family) {
    case Family::Ax:
    case Family::Rx:
    case Family::Ex:
    case Family::Mx1:
      // Protocol 1.0 error byte and Alarm LED/Shutdown bits (protocol1.md "Error").
      switch (fault) {
        case HardwareFault::InputVoltage:
          return 0x01;
        case HardwareFault::Overheating:
          return 0x04;
        case HardwareFault::Overload:
          return 0x20;
        default:
          return 0;
      }
    case Family::Xl320:
      // XL-320 Shutdown(18): bit 0 overload, bit 1 overheating, bit 2 input voltage.
      switch (fault) {
        case HardwareFault::Overload:
          return 0x01;
        case HardwareFault::Overheating:
          return 0x02;
        case HardwareFault::InputVoltage:
          return 0x04;
        default:
          return 0;
      }
    case Family::X:
    case Family::Mx2:
    case Family::P:
    case Family::Pro:
      // Shutdown / Hardware Error Status of X, MX(2.0), P and PRO.
      switch (fault) {
        case HardwareFault::InputVoltage:
          return 0x01;
        case HardwareFault::HallSensor:
          return family == Family::P || family == Family::Pro ? 0x02 : 0;
        case HardwareFault::Overheating:
          return 0x04;
        case HardwareFault::Encoder:
          return 0x08;
        case HardwareFault::ElectricalShock:
          return 0x10;
        case HardwareFault::Overload:
          return 0x20;
      }
  }
  return 0;
}

std::uint8_t fault_bits(Family family, FaultSet faults) {
  std::uint8_t bits = 0;
  for (const HardwareFault f : kFaults) {
    if ((faults & fault_set(f)) != 0) {
      bits |= fault_bit(family, f);
    }
  }
  return bits;
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
  for (const HardwareFault f : kFaults) {
    if (fault_name(f) == name) {
      return f;
    }
  }
  return std::nullopt;
}

}  // namespace dxlemu::model
