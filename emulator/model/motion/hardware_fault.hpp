#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "model/spec/family_traits.hpp"

namespace dxlemu::model {

/// A hardware error a servo can detect (includes/control_table_shutdown.md,
/// includes/control_table_alarm_shutdown.md).
enum class HardwareFault : std::uint8_t {
  InputVoltage,
  Overheating,
  Overload,
  ElectricalShock,
  Encoder,
  HallSensor,
};

/// A set of HardwareFault values, one bit each (1 << fault).
using FaultSet = std::uint8_t;

/// The set holding only `fault`.
constexpr FaultSet fault_set(HardwareFault fault) {
  return static_cast<FaultSet>(1U << static_cast<unsigned>(fault));
}

/// The bit of `fault` in `bits`, or 0 when they cannot report it.
std::uint8_t fault_bit(const FaultBits& bits, HardwareFault fault);

/// The bit of `fault` in the family's Shutdown, Hardware Error Status and Alarm LED items (and
/// the Protocol 1.0 status error byte), or 0 when the family cannot report it.
std::uint8_t fault_bit(Family family, HardwareFault fault);

/// The family's bits for every fault in `faults`.
std::uint8_t fault_bits(Family family, FaultSet faults);

/// The faults whose bits the family sets in `bits` (its Shutdown or Unload condition item).
FaultSet faults_of(Family family, std::int64_t bits);

/// The rule of `fault` in `rules`.
ErrorRule error_rule(const ErrorRules& rules, HardwareFault fault);

/// The faults whose rule in `rules` ends at `end`.
FaultSet faults_ending(const ErrorRules& rules, ErrorEnd end);

/// Every fault, in enum order.
inline constexpr std::array<HardwareFault, 6> kHardwareFaults = {
    HardwareFault::InputVoltage,    HardwareFault::Overheating, HardwareFault::Overload,
    HardwareFault::ElectricalShock, HardwareFault::Encoder,     HardwareFault::HallSensor};

/// snake_case name: input_voltage, overheating, overload, electrical_shock, encoder, hall_sensor.
std::string_view fault_name(HardwareFault fault);

/// The fault named `name`, or nullopt.
std::optional<HardwareFault> fault_from_name(std::string_view name);

}  // namespace dxlemu::model
