#include "model/motion/protection.hpp"

#include <algorithm>
#include <cmath>

namespace dxlemu::model {
namespace {

// DYNAMIXEL-Y Controller State(152) (_includes/en/dxl/y/control_table_152_controller_state.md of
// ROBOTIS-GIT/emanual). Torque on and off take no time here, so Process Torque ON/OFF (4, 6)
// and the Dynamic Brake state (3) are never shown.
constexpr std::int64_t kControllerInverterOff = 2;
constexpr std::int64_t kControllerRunning = 5;
constexpr std::int64_t kControllerHwFault = 8;

// FEETECH's protection items: thresholds in 1 % of full torque, times in 10 ms.
constexpr double kPercent = 100;
constexpr double kTenMs = 10;

}  // namespace

// "REBOOT is the only method to reset Torque Enable to '1' after the shutdown"
// (includes/control_table_shutdown.md).
TableResult Protection::refuse_torque_after_shutdown(std::int64_t value) const {
  if (value != 0 && motion_.get(motion_.items.hardware_error_status) != 0) {
    return TableResult::fail(TableError::ResultFail,
                             "Torque Enable stays 0 after a hardware error shutdown until the "
                             "servo reboots");
  }
  return {};
}

// DYNAMIXEL-Y: "If Torque cannot be enabled, the Result Fail bit ... will be set": an error that
// turned torque off (every one Error Code reports here) keeps it off.
TableResult Protection::refuse_torque_while_error_code(std::int64_t value) const {
  if (value != 0 && torque_off_error()) {
    return TableResult::fail(TableError::ResultFail,
                             "Torque Enable stays 0 while Error Code holds an error, until the "
                             "servo reboots");
  }
  return {};
}

// "To resolve the Bus Watchdog Error, you must reset Bus Watchdog(8) to '0'"
// (_includes/en/dxl/y/control_table_8_bus_watchdog.md).
void Protection::bus_watchdog_written(std::int64_t value) {
  const std::uint8_t watchdog_code = motion_.traits.error_codes.bus_watchdog;
  if (value == 0 && motion_.get(motion_.items.error_code) == watchdog_code) {
    motion_.put(motion_.items.error_code, 0);
    publish_controller_state();
  }
}

// Alarm Shutdown zeroes Torque Limit; writing it again makes the motor usable
// (ax-legacy-page-description-sections.md "Torque Limit").
void Protection::torque_limit_written() {
  v1_errors_ &= static_cast<std::uint8_t>(~fault_bits(motion_.traits.family, latched_));
  latched_ = 0;
  if (until_torque_limit_ != 0) {
    until_torque_limit_ = 0;
    show_unload();
  }
}

void Protection::position_commanded() {
  if (tripped_ == 0) {
    return;
  }
  tripped_ = 0;
  // The protection starts timing afresh: a shaft still blocked trips it again after Protection
  // time at full torque, as it did the first time.
  over_torque_ms_ = 0;
  over_current_ms_ = 0;
  show_unload();
}

void Protection::check() {
  const MotionItems& items = motion_.items;
  const MotorState& s = motion_.motor.state();
  at_limit_ms_ = s.at_limit && motion_.torque_on() ? at_limit_ms_ + motion_.motor.tick_ms() : 0;
  FaultSet detected = 0;
  const double volts = motion_.conditions.supply_v * kDeciVolt;
  if (items.min_voltage_limit &&
      (volts < static_cast<double>(motion_.get(items.min_voltage_limit)) ||
       volts > static_cast<double>(motion_.get(items.max_voltage_limit)))) {
    detected |= fault_set(HardwareFault::InputVoltage);
  }
  if (items.temperature_limit &&
      s.temperature_c >= static_cast<double>(motion_.get(items.temperature_limit))) {
    detected |= fault_set(HardwareFault::Overheating);
  }
  if (items.overload_torque && items.overload_time) {
    if (timed_overload()) {
      detected |= fault_set(HardwareFault::Overload);
    }
  } else if (at_limit_ms_ >= motion_.motor.params().overload_ms) {
    detected |= fault_set(HardwareFault::Overload);
  }
  if (timed_overcurrent()) {
    detected |= fault_set(HardwareFault::ElectricalShock);
  }
  switch (motion_.traits.error_reaction) {
    case ErrorReaction::AlarmShutdown:
      // The 1.0 Overload went with the torque it unloaded: it is reported until Torque Limit is
      // written.
      latched_ |= detected & fault_set(HardwareFault::Overload);
      alarm_shutdown(detected | injected_);
      return;
    case ErrorReaction::LatchedShutdown:
      latch(detected | injected_);
      return;
    case ErrorReaction::ErrorCode:
      latch_error_code(detected | injected_, volts);
      return;
    case ErrorReaction::Unload:
      unload(detected);
      return;
  }
}

bool Protection::timed_overload() {
  const MotionItems& items = motion_.items;
  // "Maximum torque value that starts the overload protection timer; for example 80 means 80%
  // of the maximum torque": of the full (stall) torque, the scale of Present load.
  const double threshold = static_cast<double>(motion_.get(items.overload_torque)) / kPercent *
                           motion_.motor.params().stall_torque_nm;
  const double torque = std::abs(motion_.motor.state().torque_nm);
  const bool over = motion_.torque_on() && torque > 0 && torque >= threshold;
  over_torque_ms_ = over ? over_torque_ms_ + motion_.motor.tick_ms() : 0;
  return over && over_torque_ms_ >= static_cast<double>(motion_.get(items.overload_time)) * kTenMs;
}

bool Protection::timed_overcurrent() {
  const MotionItems& items = motion_.items;
  const MotorParams& p = motion_.motor.params();
  if (!items.protection_current || !items.overcurrent_time || !p.current_unit_a) {
    return false;
  }
  const double limit =
      static_cast<double>(motion_.get(items.protection_current)) * *p.current_unit_a;
  const bool over =
      motion_.torque_on() && limit > 0 && std::abs(motion_.motor.state().current_a) >= limit;
  over_current_ms_ = over ? over_current_ms_ + motion_.motor.tick_ms() : 0;
  return over &&
         over_current_ms_ >= static_cast<double>(motion_.get(items.overcurrent_time)) * kTenMs;
}

void Protection::alarm_shutdown(FaultSet active) {
  // 1.0 Alarm Shutdown: Torque Limit goes to 0 while a selected error is present
  // (includes/control_table_alarm_shutdown.md).
  const Family family = motion_.traits.family;
  active |= latched_;
  if ((fault_bits(family, active) & motion_.get(motion_.items.shutdown)) != 0) {
    motion_.put(motion_.items.torque_limit, 0);
    at_limit_ms_ = 0;
  }
  v1_errors_ = fault_bits(family, active);
}

void Protection::unload(FaultSet detected) {
  const ErrorRules& rules = motion_.traits.error_rules;
  const FaultSet selected = faults_of(motion_.traits.family, motion_.get(motion_.items.shutdown));
  // A protection the servo trips itself stays tripped after its condition (the shaft no longer
  // pushing, the current cut) until the next position command (feetech/field-behaviour.md
  // row 7). Tripping restarts its timer. An unselected one only shows while it lasts.
  const FaultSet trips = detected & selected & faults_ending(rules, ErrorEnd::PositionCommand);
  tripped_ |= trips;
  if ((trips & fault_set(HardwareFault::Overload)) != 0) {
    over_torque_ms_ = 0;
  }
  if ((trips & fault_set(HardwareFault::ElectricalShock)) != 0) {
    over_current_ms_ = 0;
  }
  // An injected error is a condition for as long as its rule lasts, never a trip.
  conditions_ = (detected & ~trips) | injected_;
  until_torque_limit_ |=
      conditions_ & selected & faults_ending(rules, ErrorEnd::TorqueLimitWritten);
  // Over-temperature switches the torque off, again whenever it is switched on while still hot.
  for (const HardwareFault f : kHardwareFaults) {
    if ((conditions_ & selected & fault_set(f)) != 0 &&
        error_rule(rules, f).effect == ErrorEffect::TorqueOff) {
      turn_torque_off_for_error();
    }
  }
  show_unload();
}

void Protection::show_unload() {
  const MotionItems& items = motion_.items;
  const ErrorRules& rules = motion_.traits.error_rules;
  const FaultSet selected = faults_of(motion_.traits.family, motion_.get(items.shutdown));
  const FaultSet acting = (conditions_ & selected) | tripped_ | until_torque_limit_;
  double share = 1;
  for (const HardwareFault f : kHardwareFaults) {
    if ((acting & fault_set(f)) == 0) {
      continue;
    }
    switch (error_rule(rules, f).effect) {
      case ErrorEffect::Unload:
        share = 0;
        break;
      case ErrorEffect::HoldingTorque:
        // "Torque output after entering overload protection; for example 20 means 20% of the
        // maximum torque".
        share = std::min(share, static_cast<double>(motion_.get(items.holding_torque)) / kPercent);
        break;
      case ErrorEffect::TorqueOff:
        break;  // done when detected: the torque switch reads 0
    }
  }
  motion_.protection_torque_share = share;
  if (share == 0) {
    at_limit_ms_ = 0;
  }
  v1_errors_ = fault_bits(motion_.traits.family, conditions_ | tripped_);
  // FEETECH Servo status (65): the bits its status packets carry.
  motion_.put(items.servo_status, v1_errors_);
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
    turn_torque_off_for_error();
  }
}

void Protection::turn_torque_off_for_error() {
  if (motion_.torque_on()) {
    motion_.table.set(*motion_.items.torque_enable, 0);
    motion_.profile.reset();
    motion_.velocity_demand = 0;
  }
  at_limit_ms_ = 0;
}

void Protection::latch_error_code(FaultSet active, double volts) {
  // DYNAMIXEL-Y: every error this emulator detects is one whose Error Code row says Torque ON
  // 'N': it turns torque off and its number stays in Error Code (the most recent error) until
  // a reboot.
  const MotionItems& items = motion_.items;
  const ErrorCodes& codes = motion_.traits.error_codes;
  const bool over_voltage =
      items.max_voltage_limit && volts > static_cast<double>(motion_.get(items.max_voltage_limit));
  const std::pair<HardwareFault, std::uint8_t> by_fault[] = {
      {HardwareFault::InputVoltage, over_voltage ? codes.over_voltage : codes.low_voltage},
      {HardwareFault::Overheating, codes.overheating},
      {HardwareFault::Overload, codes.overload},
      {HardwareFault::ElectricalShock, codes.electrical_shock},
      {HardwareFault::Encoder, codes.encoder},
      {HardwareFault::HallSensor, codes.hall_sensor},
  };
  for (const auto& [fault, code] : by_fault) {
    if ((active & fault_set(fault)) == 0 || code == 0) {
      continue;
    }
    if (motion_.get(items.error_code) == code) {
      continue;  // already reported; "The same error does not occur multiple times"
    }
    record_error_code(code);
    turn_torque_off_for_error();
  }
  publish_controller_state();
}

void Protection::report_bus_watchdog() {
  const std::uint8_t code = motion_.traits.error_codes.bus_watchdog;
  if (code != 0 && motion_.items.error_code && !torque_off_error()) {
    record_error_code(code);  // torque stays on; the goals are refused until it is cleared
    publish_controller_state();
  }
}

bool Protection::torque_off_error() const {
  const std::int64_t code = motion_.get(motion_.items.error_code);
  return code != 0 && code != motion_.traits.error_codes.bus_watchdog;
}

void Protection::record_error_code(std::uint8_t code) {
  // _includes/en/dxl/y/control_table_error_code_history.md: Error Code shows the most recent
  // error; History 1 ~ 16 keep the errors in order, oldest first, each once, the oldest dropped
  // when a 17th comes.
  const MotionItems& items = motion_.items;
  motion_.put(items.error_code, code);
  const std::vector<std::size_t>& history = items.error_code_history;
  ControlTable& table = motion_.table;
  if (std::any_of(history.begin(), history.end(),
                  [&](std::size_t slot) { return table.get(slot) == code; })) {
    return;
  }
  const auto free = std::find_if(history.begin(), history.end(),
                                 [&](std::size_t slot) { return table.get(slot) == 0; });
  if (free != history.end()) {
    table.set(*free, code);
    return;
  }
  for (std::size_t i = 0; i + 1 < history.size(); ++i) {
    table.set(history[i], table.get(history[i + 1]));
  }
  if (!history.empty()) {
    table.set(history.back(), code);
  }
}

void Protection::publish_controller_state() {
  const MotionItems& items = motion_.items;
  if (!items.controller_state) {
    return;
  }
  const std::int64_t state = torque_off_error()    ? kControllerHwFault
                             : motion_.torque_on() ? kControllerRunning
                                                   : kControllerInverterOff;
  motion_.put(items.controller_state, state);
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
  latched_ = 0;
  conditions_ = 0;
  tripped_ = 0;
  until_torque_limit_ = 0;
  at_limit_ms_ = 0;
  over_torque_ms_ = 0;
  over_current_ms_ = 0;
  motion_.protection_torque_share = 1;
  publish_controller_state();  // Startup Configuration may have turned torque on
}

}  // namespace dxlemu::model
