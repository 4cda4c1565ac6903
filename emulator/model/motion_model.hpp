#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

#include "model/control_table.hpp"
#include "model/hardware_fault.hpp"
#include "model/motor_physics.hpp"
#include "model/profile.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::model {

/// Moves one servo: reads its goals from the control table each tick of the virtual clock, runs
/// the profile and the motor, writes the Present values back, and detects hardware errors
/// (Shutdown, Hardware Error Status, 1.0 Alarm Shutdown). Ticks are at whole multiples of the
/// tick period on the simulated clock and run lazily: advance_to() catches up on every tick due,
/// and skips ticks that change nothing, so a servo at rest costs nothing and the result is the
/// same bit for bit as ticking eagerly. Rules and choices: docs/motion.md.
class MotionModel {
 public:
  /// The model for `table`, which must outlive it; `tick` is the tick period (1 ms: 1 kHz).
  explicit MotionModel(ControlTable& table, sim::SimDuration tick = std::chrono::milliseconds(1));
  ~MotionModel();
  MotionModel(const MotionModel&) = delete;
  MotionModel& operator=(const MotionModel&) = delete;

  /// Runs every tick due up to `now` (simulated time; never goes back).
  void advance_to(sim::SimTime now);

  /// The servo's surroundings: ambient temperature, supply voltage, external load, blocked.
  const Conditions& conditions() const { return conditions_; }
  void set_conditions(const Conditions& conditions);

  /// Hardware errors forced from outside (fault injection): each is detected as if its
  /// condition were real, for as long as it is set.
  FaultSet injected() const { return injected_; }
  void set_injected(FaultSet faults);

  /// The errors a Protocol 1.0 family reports in the error byte of every status now.
  std::uint8_t v1_error_bits() const;

  /// A bus instruction or a device-side change is coming: Present values set device-side move
  /// the shaft (position), the winding (temperature) or the supply (voltage) there, and ticks no
  /// longer assume that nothing changes.
  void wake();

  /// After a reboot re-initialised the table: the shaft and the winding are where they were;
  /// the Present values say so again, Goal Position is the present position, the position is
  /// within one turn again.
  void after_reboot();

  /// The table's Present values were re-initialised (Factory Reset): they show the shaft, the
  /// winding and the supply again.
  void republish();

  /// Bus Watchdog expiry: stop and hold where the shaft is.
  void stop();

  /// Clear instruction: the position goes back within one turn.
  void clear_turns();

  /// The motor and shaft now.
  const MotorState& motor() const { return motor_.state(); }
  const MotorParams& params() const { return motor_.params(); }
  /// The tick period.
  sim::SimDuration tick() const { return tick_; }

 private:
  enum class Mode { Current, Velocity, Position, Extended, CurrentPosition, Pwm };
  struct Items;  // indices of the items the model reads and writes

  void install_hooks();
  void run_tick();
  void cool_until(sim::SimTime now);
  DriveCommand command();
  DriveCommand modern_command();
  DriveCommand classic_command();
  double compliance_offset() const;
  std::optional<Mode> mode() const;
  bool classic() const;
  bool wheel_mode() const;
  bool position_mode() const;
  bool torque_on() const;
  double direction() const;
  double homing() const;
  double torque_cap() const;
  double duty_cap() const;
  double profile_elapsed_ms() const;
  bool profile_running() const;
  void plan_to(double raw_goal);
  void hold();
  void goal_to_present();
  void on_goal_position(std::int64_t goal);
  void on_torque_enable(std::int64_t old_value, std::int64_t new_value);
  void on_operating_mode();
  double raw_goal(std::int64_t goal) const;
  bool multi_turn() const;
  std::int64_t present_position() const;
  void wrap_to_one_turn();
  void absorb_device_changes();
  void protect();
  void publish();
  void publish_modern();
  void publish_classic();
  void put(const std::optional<std::size_t>& item, std::int64_t value);
  std::int64_t get(const std::optional<std::size_t>& item, std::int64_t otherwise = 0) const;

  ControlTable& table_;
  sim::SimDuration tick_;
  sim::SimTime next_tick_;     // the next tick to run (the first is one period after power-on)
  sim::SimTime state_time_{};  // the last tick run: the motor's state is from then
  MotorPhysics motor_;
  Conditions conditions_;
  FaultSet injected_ = 0;
  std::unique_ptr<Items> items_;
  // Active: every tick runs. Cooling: only the temperature moves (cool_until()). Resting: ticks
  // change nothing and are skipped.
  enum class Activity { Active, Cooling, Resting };
  Activity activity_ = Activity::Active;
  std::optional<Profile> profile_;
  sim::SimTime profile_start_{};
  double velocity_demand_ = 0;     // velocity mode: the ramped velocity, pulses/ms
  double ramp_goal_ = 0;           // time-based velocity mode: the goal the ramp rate is for
  double ramp_rate_ = 0;           // pulses/ms², set when that goal changed
  double at_limit_ms_ = 0;         // how long the motor has been at its torque limit
  bool overload_latched_ = false;  // 1.0: until Torque Limit is written
  bool step_profile_ = false;      // the profile is a step (Profile Velocity 0): no type
  std::uint8_t v1_errors_ = 0;     // 1.0 error bits from the last tick
  struct Published {               // the Present values the last publish() wrote
    std::int64_t position = 0;
    std::int64_t temperature = 0;
    std::int64_t voltage = 0;
  };
  Published published_;
};

}  // namespace dxlemu::model
