#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

#include "model/motion/drive.hpp"
#include "model/motion/hand.hpp"
#include "model/motion/hardware_fault.hpp"
#include "model/motion/joint_coupling.hpp"
#include "model/motion/motion_context.hpp"
#include "model/motion/motor_physics.hpp"
#include "model/motion/present_values.hpp"
#include "model/motion/protection.hpp"
#include "model/table/control_table.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::model {

/// Moves one servo: reads its goals from the control table each tick of the virtual clock, runs
/// the profile and the motor, writes the Present values back, and detects hardware errors
/// (Shutdown, Hardware Error Status, 1.0 Alarm Shutdown). Ticks are at whole multiples of the
/// tick period on the simulated clock and run lazily: advance_to() catches up on every tick due,
/// and skips ticks that change nothing, so a servo at rest costs nothing and the result is the
/// same bit for bit as ticking eagerly. Its parts: the family's Drive (what the goal items mean),
/// Protection (hardware errors), PresentValues (Present values set device-side), sharing one
/// MotionContext. Rules and choices: docs/motion.md.
class MotionModel {
 public:
  /// The model for `table`, which must outlive it; `tick` is the tick period (1 ms: 1 kHz).
  explicit MotionModel(ControlTable& table, sim::SimDuration tick = std::chrono::milliseconds(1));
  ~MotionModel();
  MotionModel(const MotionModel&) = delete;
  MotionModel& operator=(const MotionModel&) = delete;

  /// Runs every tick due up to `now` (simulated time; never goes back). A servo coupled to a
  /// physics world steps that world, and with it every servo coupled to it, tick by tick.
  void advance_to(sim::SimTime now);

  /// Drives `mapping`'s joint of `clock`'s world from now on (docs/physics.md): the shaft is
  /// where the joint is, the motor's torque goes onto the joint, and the servo ticks with the
  /// world. `clock` must outlive this model. Call once, before the first tick.
  void couple(physics::WorldClock& clock, const JointMapping& mapping);
  /// True once couple() was called.
  bool coupled() const { return coupling_ != nullptr; }

  /// The servo's surroundings: ambient temperature, supply voltage, external load, blocked.
  const Conditions& conditions() const { return motion_.conditions; }
  void set_conditions(const Conditions& conditions);

  /// A hand holds the shaft from the next tick on (docs/hands.md), replacing any other; null:
  /// no hand holds it. The model shares `hand` with whoever made it.
  void set_hand(std::shared_ptr<const Hand> hand);
  /// The hand holding the shaft, or null.
  const Hand* hand() const { return hand_.get(); }

  /// Hardware errors forced from outside (fault injection): each is detected as if its
  /// condition were real, for as long as it is set.
  FaultSet injected() const { return protection_.injected(); }
  void set_injected(FaultSet faults);

  /// The errors a Protocol 1.0 family reports in the error byte of every status now.
  std::uint8_t v1_error_bits() const;

  /// A bus instruction or a device-side change is coming: Present values set device-side move
  /// the shaft (position), the winding (temperature) or the supply (voltage) there, and ticks no
  /// longer assume that nothing changes.
  void wake();

  /// Item `item` was set device-side without its write hooks (ControlTable::set): when it is a
  /// setting the Present values are computed from (MotionItems::reading_settings: Homing
  /// Offset, Drive Mode, ...), they show the new value at once, as after a bus write.
  void setting_forced(std::size_t item);

  /// After a reboot re-initialised the table: the shaft and the winding are where they were;
  /// the Present values say so again, Goal Position is the present position, the position is
  /// within one turn again.
  void after_reboot();

  /// The table's Present values were re-initialised (Factory Reset): they show the shaft, the
  /// winding and the supply again.
  void republish();

  /// Bus Watchdog expiry: stop and hold where the shaft is; DYNAMIXEL-Y also reports Bus Watchdog
  /// Error in Error Code.
  void stop();

  /// Clear instruction: the position goes back within one turn.
  void clear_turns();

  /// Sets the homing offset item so that Present Position reads `present` where the shaft is
  /// now (FEETECH Position calibration and Torque switch 128); nothing without that item. Returns
  /// false, changing nothing, when that offset lies outside the item's range.
  bool calibrate_position(std::int64_t present);

  // What bus writes of its items do to the motion; the item hook table (model/item_hooks.cpp)
  // says which item and which models.

  /// Goal Position written: the move starts (and, where the family does so, torque comes on).
  void on_goal_position(std::int64_t goal);
  /// The speed goal (Goal Velocity; FEETECH Running speed) written: in velocity mode, where the
  /// family does so, torque comes on (FamilyTraits::torque_on_by_speed_goal).
  void on_speed_goal();
  /// Torque Enable (FEETECH: Torque switch) written from `old_value` to `new_value`.
  void on_torque_enable(std::int64_t old_value, std::int64_t new_value);
  /// Operating Mode changed: the profile and the limits reset.
  void on_operating_mode();
  /// A setting the Present values are computed from changed (MotionItems::reading_settings):
  /// they show it on the very next read.
  void on_reading_setting();
  /// The range Goal Position takes in the present mode when it is not the item's own: over 512
  /// turns in Extended and Current-based Position Control Mode
  /// (includes/control_table_opmode_six_2.md), else nullopt.
  std::optional<ItemRange> extended_goal_range() const;
  /// Hardware error detection and the reaction to it.
  Protection& protection() { return protection_; }
  /// The control mode the goal items select now; nullopt: none the family knows.
  std::optional<Mode> mode() const { return drive_->mode(); }

  /// The motor and shaft now.
  const MotorState& motor() const { return motion_.motor.state(); }
  const MotorParams& params() const { return motion_.motor.params(); }
  /// The tick period.
  sim::SimDuration tick() const { return tick_; }
  /// Nothing moves until an input does: advance_to() skips the ticks due (a servo at rest).
  bool resting() const { return activity_ == Activity::Resting; }

 private:
  friend class JointCoupling;
  // A coupled tick in two halves around the world's steps: the motor's torque for the tick
  // ending at `tick_end` (N·m at the shaft), then the shaft where the world moved it.
  double begin_coupled_tick(sim::SimTime tick_end);
  /// The hand's torque on a coupled shaft for the tick ending at `tick_end`, N·m at the shaft
  /// (0 without a hand).
  double coupled_hand_torque(sim::SimTime tick_end) const;
  void end_coupled_tick(double position, double velocity);
  void publish_realtime_tick(sim::SimTime now);
  void run_tick();
  void cool_until(sim::SimTime now);
  DriveCommand command();
  bool position_mode() const { return is_position_mode(drive_->mode()); }
  /// The motor position, pulses, a Goal Position write of `goal` sends the motor to: relative
  /// in step mode, within the position limits where the family clamps goals.
  double goal_target(std::int64_t goal) const;
  /// `goal` clamped to Min ~ Max Position Limit, to the nearer limit around the turn while the
  /// feedback is single-turn (FEETECH: "wrap-aware"); unchanged when both limits are 0.
  std::int64_t goal_within_limits(std::int64_t goal) const;
  /// Torque off, a goal written: torque comes on where the family's TorqueOnByGoal says so.
  /// False when it stays off.
  bool torque_on_by_goal();
  void hold();
  void publish();
  void absorb_device_changes();

  sim::SimDuration tick_;
  sim::SimTime next_tick_;  // the next tick to run (the first is one period after power-on)
  MotionContext motion_;
  std::unique_ptr<Drive> drive_;
  Protection protection_;
  PresentValues present_;
  // Active: every tick runs. Cooling: only the temperature moves (cool_until()). Resting: ticks
  // change nothing and are skipped.
  enum class Activity { Active, Cooling, Resting };
  Activity activity_ = Activity::Active;
  std::unique_ptr<JointCoupling> coupling_;
  std::shared_ptr<const Hand> hand_;
};

}  // namespace dxlemu::model
