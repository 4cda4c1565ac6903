#pragma once

#include <cstdint>

#include "model/motion/hardware_fault.hpp"
#include "model/motion/motion_context.hpp"
#include "model/table/table_result.hpp"

namespace dxlemu::model {

/// Detects one servo's hardware errors after each tick (supply voltage outside its limits,
/// winding over Temperature Limit, the motor at its torque limit for the Overload time or, where
/// the model has FEETECH's timed protections, over Overload torque for Protection time and over
/// Protection current for Overcurrent protection time, and the errors forced from outside) and
/// reacts as its family does (FamilyTraits::error_reaction): Alarm Shutdown, a latched Shutdown,
/// DYNAMIXEL-Y's Error Code, or FEETECH's Unload condition. Keeps DYNAMIXEL-Y's Controller
/// State(152) in step with torque and errors. docs/motion.md "Hardware errors".
class Protection {
 public:
  /// Protection working on `motion`, which must outlive it.
  explicit Protection(MotionContext& motion) : motion_(motion) {}

  // What writes of its items do to the reaction; the item hook table (model/item_hooks.cpp)
  // says which item and which models.

  /// Torque Enable `value` is refused while Hardware Error Status holds an error: "REBOOT is the
  /// only method to reset Torque Enable to '1' after the shutdown".
  TableResult refuse_torque_after_shutdown(std::int64_t value) const;
  /// DYNAMIXEL-Y: Torque Enable `value` is refused while Error Code holds an error that turned
  /// torque off.
  TableResult refuse_torque_while_error_code(std::int64_t value) const;
  /// Bus Watchdog written `value`: 0 clears a Bus Watchdog error reported in Error Code.
  void bus_watchdog_written(std::int64_t value);
  /// Torque Limit written: a 1.0 Alarm Shutdown's latched errors (Overload) end; so do the
  /// effects of errors whose rule ends there (ErrorEnd::TorqueLimitWritten).
  void torque_limit_written();
  /// A position command arrived (FEETECH: a Goal position write, or Running speed in wheel
  /// mode): the protections tripped until then (ErrorEnd::PositionCommand) end at once, in time
  /// for the command's own status.
  void position_commanded();
  /// Controller State (DYNAMIXEL-Y) shows torque and errors as they are now.
  void publish_controller_state();

  /// Hardware errors forced from outside (fault injection): each is detected as if its
  /// condition were real, for as long as it is set.
  FaultSet injected() const { return injected_; }
  void set_injected(FaultSet faults) { injected_ = faults; }

  /// Checks the motor's state after a tick and reacts: a shutdown turns torque off (or sets
  /// Torque Limit to 0, or unloads the motor) and ends the move.
  void check();

  /// The errors a Protocol 1.0 status reports in its error byte now: the 1.0 families' errors
  /// of the last check, or a 2.0 model's latched errors in the 1.0 bits.
  std::uint8_t v1_error_bits() const;

  /// Bus Watchdog expiry, where the family reports it in Error Code (ErrorCodes::bus_watchdog).
  void report_bus_watchdog();

  /// Power-on or reboot: no Overload building up or latched, no protection tripped; Controller
  /// State shows torque.
  void reset();

 private:
  /// True while Error Code holds an error that keeps torque off (every one but Bus Watchdog).
  bool torque_off_error() const;
  /// FEETECH's overload protection: true once the motor's torque has been at Overload torque
  /// for Protection time.
  bool timed_overload();
  /// FEETECH's overcurrent protection: true once Present current has been at Protection current
  /// for Overcurrent protection time.
  bool timed_overcurrent();
  void alarm_shutdown(FaultSet active);
  /// ErrorReaction::Unload after a check: `detected` are the errors the servo found itself.
  void unload(FaultSet detected);
  /// ErrorReaction::Unload: the motor's torque and the status bits as the errors now say.
  void show_unload();
  void latch(FaultSet active);
  void latch_error_code(FaultSet active, double volts);
  /// A latched error turns torque off: the motor stops driving and the profile ends.
  void turn_torque_off_for_error();
  void record_error_code(std::uint8_t code);

  MotionContext& motion_;
  FaultSet injected_ = 0;
  double at_limit_ms_ = 0;      // how long the motor has been at its torque limit
  double over_torque_ms_ = 0;   // how long over FEETECH's Overload torque
  double over_current_ms_ = 0;  // how long at FEETECH's Protection current
  // 1.0 Alarm Shutdown: errors that went with the torque they unloaded (Overload), reported
  // until Torque Limit is written.
  FaultSet latched_ = 0;
  // ErrorReaction::Unload: the conditions of the last check (a trip takes its condition over),
  // the protections tripped until the next position command, and the errors whose effect lasts
  // until Torque limit is written.
  FaultSet conditions_ = 0;
  FaultSet tripped_ = 0;
  FaultSet until_torque_limit_ = 0;
  std::uint8_t v1_errors_ = 0;  // 1.0 error bits from the last check
};

}  // namespace dxlemu::model
