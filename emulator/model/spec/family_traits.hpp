#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "wire/protocol_table.hpp"
#include "wire/status_error.hpp"

namespace dxlemu::model {

/// Behaviour family: which rules of the e-Manual a model follows beyond its control table. Each
/// family is one row of the traits table (family_traits.cpp), in this order.
enum class Family { X, Mx2, Mx1, Ax, Rx, Ex, Xl320, P, Pro, Dx, ProA, Y, Sts, Sms, Scs, Hls };

/// Who makes a family's servos. A bus port speaks one maker's protocol, and model numbers are
/// unique only within one maker's models (docs/feetech.md "One maker per port").
enum class Maker { Robotis, Feetech };

/// The name of a maker in messages: "ROBOTIS" or "FEETECH".
constexpr std::string_view maker_name(Maker maker) {
  return maker == Maker::Feetech ? "FEETECH" : "ROBOTIS";
}

/// How a family's goal items select a control mode and move the motor, and how the motor shows
/// in its Present motion items: one implementation of model/motion/drive.hpp each.
enum class DriveKind {
  /// Joint or wheel mode by CW/CCW Angle Limit (XL-320: Control Mode); Moving Speed and Torque
  /// Limit; positions within one turn; Compliance (AX, RX, EX); Present Speed and Load as a
  /// 0 ~ 1023 magnitude with a direction bit (model/motion/joint_wheel_drive.*).
  JointWheel,
  /// Operating Mode selects current, velocity, position, extended position, current-based
  /// position or PWM control; Profile Velocity/Acceleration and Drive Mode shape the moves
  /// (model/motion/operating_mode_drive.*).
  OperatingMode,
};

/// The range Goal Position takes in Extended and Current-based Position Control Mode.
enum class ExtendedGoals {
  /// No rule: the item's own range and limit items (PRO, and families without those modes).
  ItemRange,
  /// -256 ~ 256 turns (X, MX(2.0): includes/control_table_opmode_six_2.md).
  Turns,
  /// The item's whole signed width (P).
  ItemWidth,
};

/// Whether writing Goal Position turns torque on.
enum class TorqueOnByGoal {
  Never,
  /// Always (Protocol 1.0 families: a goal write makes the servo move).
  Always,
  /// When Drive Mode's Torque On by Goal Update bit is set (includes/control_table_drivemode.md).
  DriveModeBit,
};

/// What torque on does to the goal.
enum class TorqueOnGoal {
  /// The servo moves to Goal Position (Protocol 1.0 families: power-on set it to where the shaft
  /// was).
  MovesToGoal,
  /// The servo holds where it is: Goal Position takes the present position, so torque on never
  /// makes it jump (docs/motion.md).
  Holds,
};

/// How hardware errors stop the servo.
enum class ErrorReaction {
  /// Protocol 1.0 Alarm Shutdown: the errors are in the error byte of every status while they
  /// last; one selected in Alarm Shutdown sets Torque Limit to 0; Overload lasts until Torque
  /// Limit is written (includes/control_table_alarm_shutdown.md).
  AlarmShutdown,
  /// An error selected in Shutdown latches in Hardware Error Status and turns torque off; only a
  /// reboot clears it (includes/control_table_shutdown.md).
  LatchedShutdown,
  /// DYNAMIXEL-Y: no Shutdown item; every detected error turns torque off and latches its number
  /// in Error Code(153), the last ones kept in Error Code History; only a reboot clears it here
  /// (the Error Clear packet is not emulated). FamilyTraits::error_codes gives the numbers.
  ErrorCode,
  /// FEETECH Unload condition: the errors are in the error byte of every status and in Servo
  /// status while they last; each one the shutdown item selects acts on the motor and ends as
  /// FamilyTraits::error_rules says. No item is rewritten but the torque switch of an error whose
  /// effect is ErrorEffect::TorqueOff (docs/feetech.md "Status bits").
  Unload,
};

/// What a hardware error the shutdown item selects does to the motor (ErrorReaction::Unload).
enum class ErrorEffect : std::uint8_t {
  /// The motor gives no torque; the torque item and the torque limit keep their values.
  Unload,
  /// The motor gives at most the Holding torque item's share of its full torque.
  HoldingTorque,
  /// The torque item goes to 0, again whenever it is switched on while the error lasts.
  TorqueOff,
};

/// When a hardware error the shutdown item selects ends (ErrorReaction::Unload). One it does not
/// select shows while its condition lasts and does nothing else.
enum class ErrorEnd : std::uint8_t {
  /// With its condition: its bit and its effect.
  Condition,
  /// Once the servo's own protection has tripped, its bit and its effect last until the next
  /// position command (a Goal position write; in wheel mode, a Running speed write). An injected
  /// error is not a trip: it lasts while its rule lasts.
  PositionCommand,
  /// Its bit with its condition; its effect until the torque limit item is written (the
  /// Protocol 1.0 Alarm Shutdown's recovery, without zeroing the item).
  TorqueLimitWritten,
};

/// What one hardware error does and when it ends (ErrorReaction::Unload).
struct ErrorRule {
  ErrorEffect effect = ErrorEffect::Unload;
  ErrorEnd end = ErrorEnd::Condition;
};

/// The rule of each hardware error (ErrorReaction::Unload).
struct ErrorRules {
  ErrorRule input_voltage;     ///< supply outside the voltage limits
  ErrorRule overheating;       ///< winding at the temperature limit
  ErrorRule overload;          ///< the overload protection
  ErrorRule electrical_shock;  ///< the overcurrent protection
  ErrorRule encoder;           ///< the position sensor
  ErrorRule hall_sensor;       ///< the motor's Hall sensor
};

/// Which models of a family take part in Fast Sync Read and Fast Bulk Read.
enum class FastRead {
  None,
  /// Single-axis models only (X: not 2XL430/2XC430; protocol2.md "Fast Sync Read").
  SingleAxis,
  All,
};

/// The bit of each hardware error in a family's Shutdown, Hardware Error Status and Alarm LED
/// items (and the Protocol 1.0 status error byte); 0: the family cannot report it.
struct FaultBits {
  std::uint8_t input_voltage = 0;     ///< Input Voltage Error
  std::uint8_t overheating = 0;       ///< Overheating Error
  std::uint8_t overload = 0;          ///< Overload Error
  std::uint8_t electrical_shock = 0;  ///< Electrical Shock Error
  std::uint8_t encoder = 0;           ///< Motor Encoder Error
  std::uint8_t hall_sensor = 0;       ///< Motor Hall Sensor Error
};

/// The Operating Mode value that selects each control mode; nullopt: the family has no such mode
/// (or the emulator does not model it). DYNAMIXEL's values by default
/// (includes/control_table_opmode_six_2.md).
struct OperatingModeValues {
  std::optional<std::int64_t> current = 0;           ///< current (torque) control
  std::optional<std::int64_t> velocity = 1;          ///< velocity (wheel) control
  std::optional<std::int64_t> position = 3;          ///< position control within one turn
  std::optional<std::int64_t> extended = 4;          ///< extended (multi-turn) position control
  std::optional<std::int64_t> current_position = 5;  ///< current-based position control
  std::optional<std::int64_t> pwm = 16;              ///< PWM (open loop) control
  std::optional<std::int64_t> step = std::nullopt;   ///< FEETECH step mode (relative goals)
};

/// What a FEETECH servo does when it refuses a packet, where FEETECH defines no error bit to say
/// so (docs/feetech.md "Refusals"): per class of refusal, a status with a bit (0: none, the
/// refusal shows only in what did not change) or no status at all. A model file may replace
/// them (`"refusal_bits"`).
struct Refusals {
  wire::RefusalAnswer checksum;     ///< a packet with a wrong checksum sent to the servo's ID
  wire::RefusalAnswer instruction;  ///< an unknown instruction, or one it cannot make out
  wire::RefusalAnswer read;         ///< a Read or Sync Read part outside the control table
  wire::RefusalAnswer range;        ///< a write, or an instruction's setting, it refuses
  bool operator==(const Refusals&) const = default;

  /// The answer of `refusal_class` (RefusalClass::None: a status with no bit).
  wire::RefusalAnswer of(wire::RefusalClass refusal_class) const;
};

/// The Error Code(153) value of each hardware error (ErrorReaction::ErrorCode); 0: the family
/// cannot report it.
struct ErrorCodes {
  std::uint8_t over_voltage = 0;      ///< supply above Max Voltage Limit
  std::uint8_t low_voltage = 0;       ///< supply below Min Voltage Limit
  std::uint8_t overheating = 0;       ///< winding above the (motor) Temperature Limit
  std::uint8_t overload = 0;          ///< Overload Error
  std::uint8_t electrical_shock = 0;  ///< the family's nearest error to Electrical Shock
  std::uint8_t encoder = 0;           ///< Encoder Error
  std::uint8_t hall_sensor = 0;       ///< Hall Sensor Error
  /// Bus Watchdog Error: unlike the others it keeps torque on ("Torque ON: Y") and is cleared by
  /// writing 0 to Bus Watchdog.
  std::uint8_t bus_watchdog = 0;
};

/// Everything a family does differently from the others that its model files cannot say. One
/// row per family (family_traits.cpp) is the one place a family is added, of this maker or
/// another (docs/model-format.md "Adding a family"): what no trait covers becomes a new trait,
/// read where the behaviour is. The defaults are what a family without the trait does.
struct FamilyTraits {
  Family family = Family::X;
  /// The family's name in model files (`"family": "x"`).
  std::string_view name = {};
  /// Who makes it.
  Maker maker = Maker::Robotis;
  /// How the goal items move the motor and the Present motion items show it.
  DriveKind drive = DriveKind::OperatingMode;
  /// In joint mode Goal Position must lie between CW and CCW Angle Limit, else Angle Limit
  /// Error (includes/ax-legacy-page-description-sections.md; model/table/family_rules.*).
  bool goal_within_angle_limits = false;
  /// Both angle limits at this value select multi-turn mode: any Goal Position, the position
  /// absolute over turns (MX 1.0: 4095, includes/control_table_mx_angle_limit.md).
  std::optional<std::int64_t> multi_turn_angle_limit = std::nullopt;
  /// In position mode the motor goes no further than Min ~ Max Position Limit, whatever Goal
  /// Position says (FEETECH Minimum/Maximum angle limit, "the limit of motion stroke"); both at
  /// 0 lift the limit ("0 when the multi-turn absolute position control is adopted").
  bool goal_clamped_to_position_limits = false;
  /// EEPROM items are locked while Torque Enable is 1 (includes/control_table.md); otherwise
  /// through the Lock item, when the model has one.
  bool eeprom_locked_by_torque = false;
  /// Goal Position's range in Extended and Current-based Position Control Mode.
  ExtendedGoals extended_goals = ExtendedGoals::ItemRange;
  /// Whether a Goal Position write turns torque on.
  TorqueOnByGoal torque_on_by_goal = TorqueOnByGoal::Never;
  /// What torque on does to the goal.
  TorqueOnGoal torque_on_goal = TorqueOnGoal::Holds;
  /// Present Position returns within one turn at power-on and reboot: the turn count is lost
  /// (includes/control_table_opmode_note.md; FEETECH's full-angle feedback, "the turn count is
  /// lost at power-off"); otherwise the shaft's turn is kept.
  bool one_turn_at_boot = false;
  /// Present Position returns within one turn at torque on in Position Control Mode
  /// (includes/control_table_opmode_note.md).
  bool one_turn_at_torque_on = false;
  /// The bit of the Phase item (FEETECH's address 18) that selects full-angle position feedback:
  /// while it is clear Present Position is the angle within one turn, wrapping at 0 and one turn
  /// (docs/feetech.md "Angle feedback"); 0: no such bit, Present Position counts turns.
  std::uint8_t full_angle_phase_bit = 0;
  /// Writing the speed goal (Goal Velocity; FEETECH Running speed) in velocity (wheel) mode
  /// turns torque on, as a Goal Position write does in position mode (TorqueOnByGoal::Always).
  bool torque_on_by_speed_goal = false;
  /// Drive Mode bit 0 reverses positions, velocities, currents and PWM
  /// (includes/control_table_drivemode.md). MX 1.0 and EX use that bit for dual-servo mode.
  bool drive_mode_reverses = false;
  /// How hardware errors stop the servo.
  ErrorReaction error_reaction = ErrorReaction::LatchedShutdown;
  /// Where each hardware error shows.
  FaultBits fault_bits = {};
  /// The Error Code of each hardware error (ErrorReaction::ErrorCode).
  ErrorCodes error_codes = {};
  /// What each hardware error does and when it ends (ErrorReaction::Unload).
  ErrorRules error_rules = {};
  /// Moving Status also reports Moving (bit 2) and Position In Range (bit 6: Present Position
  /// within Min/Max Position Limit), as DYNAMIXEL-Y does; otherwise those bits stay 0.
  bool moving_status_motion_and_range = false;
  /// Protocol 1.0 generation firmware (AX, RX, EX, MX 1.0): Baud Rate values its table does not
  /// list run at 2,000,000 / (n + 1) bps (includes/control_table_baudrate.md).
  bool protocol1_firmware = false;
  /// Knows the Reboot instruction (protocol1.md "Reboot": MX (v40+), MX(2.0) and X; AX, RX and
  /// EX answer it with Instruction Error).
  bool reboot = true;
  /// Which models take part in Fast Sync/Bulk Read (protocol2.md).
  FastRead fast_read = FastRead::None;
  /// Executes the Protocol 1.0 Bulk Read (protocol1.md: MX, MX(2.0), X).
  bool v1_bulk_read = false;
  /// Answers Reboot with a status before it reboots; FEETECH's Restart sends none
  /// (protocol-ft-scs.md: "status frame: none").
  bool reboot_status = true;
  /// The Operating Mode value of each control mode.
  OperatingModeValues operating_modes = {};
  /// A change of Operating Mode zeroes the profile and resets the goal limits
  /// (includes/control_table_opmode_six_2.md); FEETECH says nothing of it.
  bool mode_change_resets_goals = true;
  /// Torque Limit caps the motor's torque in 0.1 % of its stall torque under Operating Mode
  /// control (FEETECH Torque limit, 48); the JointWheel families read it anyway.
  bool torque_limit_caps_torque = false;
  /// Present Position is the shaft position minus the homing offset item (FEETECH's Position
  /// offset, as LeRobot states it); otherwise plus it (DYNAMIXEL's Homing Offset).
  bool homing_offset_subtracts = false;
  /// A Secondary ID item is a group address (DYNAMIXEL's Shadow ID, docs/servo.md); FEETECH's
  /// HLS Secondary ID has no documented meaning and addresses nothing here.
  bool secondary_id_addresses = true;
  /// The status levels of the status return item: at `status_level_all` the servo answers
  /// everything, at `status_level_reads` Ping and Read only, below that Ping only. DYNAMIXEL
  /// Status Return Level 2 / 1; FEETECH Response level 1 / 0.
  std::int64_t status_level_all = 2;
  std::int64_t status_level_reads = 1;
  /// Return delay item values below this count as this (SMS: "a setting below 50 still
  /// defaults to 50").
  std::int64_t min_return_delay = 0;
  /// Writing this value to the torque item calibrates Present Position to `calibrated_position`
  /// (STS and SMS Torque switch 128); nullopt: no such value.
  std::optional<std::int64_t> calibrate_torque_value = std::nullopt;
  std::int64_t calibrated_position = 0;
  /// The Lock flag item (FEETECH's `lock_flag`) decides whether EEPROM writes survive power-off:
  /// those made while it is 1 are lost (docs/feetech.md "Lock"). It never refuses a write.
  bool lock_flag_keeps_eeprom = false;
  /// What a FEETECH servo answers to refusals (FEETECH families only).
  Refusals refusals = {};
};

/// The Protocol 1.0 error bits of the hardware errors (protocol1.md "Error"), which are also the
/// Alarm LED and Alarm Shutdown bits of the Protocol 1.0 families.
inline constexpr FaultBits kProtocol1FaultBits = {.input_voltage = wire::v1_error::kInputVoltage,
                                                  .overheating = wire::v1_error::kOverheating,
                                                  .overload = wire::v1_error::kOverload};

/// The traits of `family`.
const FamilyTraits& traits_of(Family family);

/// The family's name in model files ("x", "mx2", ...).
std::string_view family_name(Family family);

/// The family named `name`, or nullopt.
std::optional<Family> family_from_name(std::string_view name);

/// Every family's name, in table order, comma-separated ("x, mx2, ...").
std::string family_names();

}  // namespace dxlemu::model
