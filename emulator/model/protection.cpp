#include "model/protection.hpp"

namespace dxlemu::model {

void Protection::install_hooks() {
  ControlTable& table = motion_.table;
  const MotionItems& items = motion_.items;
  // "REBOOT is the only method to reset Torque Enable to '1' after the shutdown"
  // (includes/control_table_shutdown.md): refused while Hardware Error Status holds an error.
  if (items.torque_enable && items.hardware_error_status) {
    table.add_validator("torque_enable", [this](std::size_t, std::int64_t v) {
      if (v != 0 && motion_.get(motion_.items.hardware_error_status) != 0) {
        return TableResult::fail(TableError::ResultFail,
                                 "Torque Enable stays 0 after a hardware error shutdown until "
                                 "the servo reboots");
      }
      return TableResult{};
    });
  }
  if (items.torque_limit && motion_.traits.error_reaction == ErrorReaction::AlarmShutdown) {
    // Alarm Shutdown zeroes Torque Limit; writing it again makes the motor usable
    // (ax-legacy-page-description-sections.md "Torque Limit").
    table.on_write("torque_limit", [this](std::size_t, std::int64_t, std::int64_t) {
      overload_latched_ = false;
      v1_errors_ &=
          static_cast<std::uint8_t>(~fault_bit(motion_.traits.fault_bits, HardwareFault::Overload));
    });
  }
}

void Protection::check() {
  const MotionItems& items = motion_.items;
  const MotorState& s = motion_.motor.state();
  at_limit_ms_ = s.at_limit && motion_.torque_on() ? at_limit_ms_ + motion_.motor.tick_ms() : 0;
  FaultSet active = injected_;
  const double volts = motion_.conditions.supply_v * kDeciVolt;
  if (items.min_voltage_limit &&
      (volts < static_cast<double>(motion_.get(items.min_voltage_limit)) ||
       volts > static_cast<double>(motion_.get(items.max_voltage_limit)))) {
    active |= fault_set(HardwareFault::InputVoltage);
  }
  if (items.temperature_limit &&
      s.temperature_c >= static_cast<double>(motion_.get(items.temperature_limit))) {
    active |= fault_set(HardwareFault::Overheating);
  }
  if (at_limit_ms_ >= motion_.motor.params().overload_ms) {
    active |= fault_set(HardwareFault::Overload);
    overload_latched_ = true;
  }
  switch (motion_.traits.error_reaction) {
    case ErrorReaction::AlarmShutdown:
      alarm_shutdown(active);
      return;
    case ErrorReaction::LatchedShutdown:
      latch(active);
      return;
  }
}

void Protection::alarm_shutdown(FaultSet active) {
  // 1.0 Alarm Shutdown: Torque Limit goes to 0 while a selected error is present
  // (includes/control_table_alarm_shutdown.md).
  const Family family = motion_.traits.family;
  if (overload_latched_) {
    active |= fault_set(HardwareFault::Overload);
  }
  if ((fault_bits(family, active) & motion_.get(motion_.items.shutdown)) != 0) {
    motion_.put(motion_.items.torque_limit, 0);
    at_limit_ms_ = 0;
  }
  v1_errors_ = fault_bits(family, active);
}

void Protection::latch(FaultSet active) {
  // X, MX(2.0), P, PRO, XL-320: an error selected in Shutdown latches in Hardware Error Status
  // and turns torque off; only a reboot clears it (includes/control_table_shutdown.md).
  const MotionItems& items = motion_.items;
  const std::uint8_t selected =
      fault_bits(motion_.traits.family, active) & motion_.get(items.shutdown);
  const auto status = static_cast<std::uint8_t>(motion_.get(items.hardware_error_status));
  if ((selected & ~status) != 0) {
    motion_.put(items.hardware_error_status, status | selected);
    if (motion_.torque_on()) {
      motion_.table.set(*items.torque_enable, 0);
      motion_.profile.reset();
      motion_.velocity_demand = 0;
    }
    at_limit_ms_ = 0;
  }
}

std::uint8_t Protection::v1_error_bits() const {
  const MotionItems& items = motion_.items;
  if (!items.hardware_error_status) {
    return v1_errors_;
  }
  // A 2.0 model speaking Protocol 1.0 shows its latched errors with the 1.0 bits.
  const auto status = motion_.get(items.hardware_error_status);
  std::uint8_t bits = 0;
  for (const HardwareFault f :
       {HardwareFault::InputVoltage, HardwareFault::Overheating, HardwareFault::Overload}) {
    if ((status & fault_bit(motion_.traits.fault_bits, f)) != 0) {
      bits |= fault_bit(kProtocol1FaultBits, f);
    }
  }
  return bits;
}

void Protection::reset() {
  overload_latched_ = false;
  at_limit_ms_ = 0;
}

}  // namespace dxlemu::model
