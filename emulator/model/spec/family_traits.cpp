#include "model/spec/family_traits.hpp"

#include <array>
#include <cstddef>

namespace dxlemu::model {
namespace {

// Shutdown / Hardware Error Status of X and MX(2.0) (includes/control_table_shutdown.md).
constexpr FaultBits kXFaultBits = {.input_voltage = 0x01,
                                   .overheating = 0x04,
                                   .overload = 0x20,
                                   .electrical_shock = 0x10,
                                   .encoder = 0x08};
// P and PRO report the motor's Hall sensor too (bit 1).
constexpr FaultBits kPFaultBits = {.input_voltage = 0x01,
                                   .overheating = 0x04,
                                   .overload = 0x20,
                                   .electrical_shock = 0x10,
                                   .encoder = 0x08,
                                   .hall_sensor = 0x02};
// XL-320 Shutdown(18): bit 0 overload, bit 1 overheating, bit 2 input voltage.
constexpr FaultBits kXl320FaultBits = {
    .input_voltage = 0x04, .overheating = 0x02, .overload = 0x01};

// MX 1.0 multi-turn mode: both angle limits at 4095 (includes/control_table_mx_angle_limit.md).
constexpr std::int64_t kMx1MultiTurnLimit = 4095;

constexpr FamilyTraits with_name(FamilyTraits row, Family family, std::string_view name) {
  row.family = family;
  row.name = name;
  return row;
}

// A row names the traits where the family differs from the defaults in family_traits.hpp; a
// family like another is that row with its differences.

constexpr FamilyTraits kX = {.family = Family::X,
                             .name = "x",
                             .drive = DriveKind::OperatingMode,
                             .eeprom_locked_by_torque = true,
                             .extended_goals = ExtendedGoals::Turns,
                             .torque_on_by_goal = TorqueOnByGoal::DriveModeBit,
                             .torque_on_goal = TorqueOnGoal::Holds,
                             .one_turn_at_boot = true,
                             .one_turn_at_torque_on = true,
                             .drive_mode_reverses = true,
                             .error_reaction = ErrorReaction::LatchedShutdown,
                             .fault_bits = kXFaultBits,
                             .fast_read = FastRead::SingleAxis,
                             .v1_bulk_read = true};

constexpr FamilyTraits kMx2 = [] {
  FamilyTraits row = with_name(kX, Family::Mx2, "mx2");
  row.fast_read = FastRead::None;
  return row;
}();

constexpr FamilyTraits kP = [] {
  FamilyTraits row = with_name(kX, Family::P, "p");
  row.extended_goals = ExtendedGoals::ItemWidth;
  row.fault_bits = kPFaultBits;
  row.fast_read = FastRead::All;
  row.v1_bulk_read = false;
  return row;
}();

// PRO: no Drive Mode item, no extended goal range, Protocol 2.0 only.
constexpr FamilyTraits kPro = [] {
  FamilyTraits row = with_name(kP, Family::Pro, "pro");
  row.extended_goals = ExtendedGoals::ItemRange;
  row.drive_mode_reverses = false;
  row.fast_read = FastRead::None;
  return row;
}();

// PRO(A): the DYNAMIXEL-P firmware on PRO hardware (the P table and rules), without the Fast
// Sync/Bulk Read that protocol2.md lists for P and X only.
constexpr FamilyTraits kProA = [] {
  FamilyTraits row = with_name(kP, Family::ProA, "pro_a");
  row.fast_read = FastRead::None;
  return row;
}();

// DYNAMIXEL-Y Error Code values (_includes/en/dxl/y/control_table_153_error_code.md of
// ROBOTIS-GIT/emanual): 1 Over Voltage, 2 Low Voltage, 4 Motor Overheating, 5 Overload,
// 7 Inverter Error (the nearest to an electrical shock), 13 Encoder Error, 14 Hall Sensor Error,
// 18 Bus Watchdog Error.
constexpr ErrorCodes kYErrorCodes = {.over_voltage = 1,
                                     .low_voltage = 2,
                                     .overheating = 4,
                                     .overload = 5,
                                     .electrical_shock = 7,
                                     .encoder = 13,
                                     .hall_sensor = 14,
                                     .bus_watchdog = 18};

// DYNAMIXEL-Y: the P rules where its pages are silent (docs/families.md "DYNAMIXEL-Y"), with
// Operating Mode 0, 1, 3 only (Goal Position within the position limits, no extended range),
// a multi-turn position kept over power cycles ("DYNAMIXEL-Y stores persistent Multi-turn
// information"), Drive Mode without the Torque On by Goal Update bit, Error Code instead of
// Shutdown / Hardware Error Status, and no Fast Sync/Bulk Read (protocol2.md lists no Y servo).
constexpr FamilyTraits kY = [] {
  FamilyTraits row = with_name(kP, Family::Y, "y");
  row.extended_goals = ExtendedGoals::ItemRange;
  row.torque_on_by_goal = TorqueOnByGoal::Never;
  row.one_turn_at_boot = false;
  row.one_turn_at_torque_on = false;
  row.error_reaction = ErrorReaction::ErrorCode;
  row.fault_bits = {};
  row.error_codes = kYErrorCodes;
  row.moving_status_motion_and_range = true;
  row.fast_read = FastRead::None;
  return row;
}();

// AX, and RX, EX and DX like it.
constexpr FamilyTraits kAx = {.family = Family::Ax,
                              .name = "ax",
                              .drive = DriveKind::JointWheel,
                              .goal_within_angle_limits = true,
                              .torque_on_by_goal = TorqueOnByGoal::Always,
                              .torque_on_goal = TorqueOnGoal::MovesToGoal,
                              .error_reaction = ErrorReaction::AlarmShutdown,
                              .fault_bits = kProtocol1FaultBits,
                              .protocol1_firmware = true,
                              .reboot = false};

constexpr FamilyTraits kMx1 = [] {
  FamilyTraits row = with_name(kAx, Family::Mx1, "mx1");
  row.multi_turn_angle_limit = kMx1MultiTurnLimit;
  row.v1_bulk_read = true;
  row.reboot = true;
  return row;
}();

// XL-320: a Protocol 2.0 servo with the joint and wheel modes of the 1.0 families.
constexpr FamilyTraits kXl320 = {.family = Family::Xl320,
                                 .name = "xl320",
                                 .drive = DriveKind::JointWheel,
                                 .goal_within_angle_limits = true,
                                 .eeprom_locked_by_torque = true,
                                 .torque_on_goal = TorqueOnGoal::MovesToGoal,
                                 .error_reaction = ErrorReaction::LatchedShutdown,
                                 .fault_bits = kXl320FaultBits};

// FEETECH's Servo status bits (address 65, the status packet's ERROR byte) as the wiki lists them
// per series (feetech/README.md "Status packet"): STS and SMS use bits 0, 1, 2, 3, 5; SCSCL has
// no magnetic encoder or current bit; HLS has no load bit. The current bit reports what dxlemu
// calls an electrical shock (an overcurrent).
constexpr FaultBits kStsFaultBits = {.input_voltage = wire::feetech_error::kVoltage,
                                     .overheating = wire::feetech_error::kOverheat,
                                     .overload = wire::feetech_error::kOverload,
                                     .electrical_shock = wire::feetech_error::kOverCurrent,
                                     .encoder = wire::feetech_error::kAngleSensor};
constexpr FaultBits kScsFaultBits = {.input_voltage = wire::feetech_error::kVoltage,
                                     .overheating = wire::feetech_error::kOverheat,
                                     .overload = wire::feetech_error::kOverload};
constexpr FaultBits kHlsFaultBits = {.input_voltage = wire::feetech_error::kVoltage,
                                     .overheating = wire::feetech_error::kOverheat,
                                     .electrical_shock = wire::feetech_error::kOverCurrent,
                                     .encoder = wire::feetech_error::kAngleSensor};

// FEETECH Operating mode (address 33): 0 position, 1 constant speed (wheel), 2 PWM open loop,
// 3 step ("the number of step progress is represented by parameter 0x2a").
constexpr OperatingModeValues kFeetechModes = {.current = std::nullopt,
                                               .velocity = 1,
                                               .position = 0,
                                               .extended = std::nullopt,
                                               .current_position = std::nullopt,
                                               .pwm = 2,
                                               .step = 3};

// Torque switch 128 "calibrate the current position to 2048" (STS and SMS tables).
constexpr std::int64_t kTorqueCalibrate = 128;
constexpr std::int64_t kMiddlePosition = 2048;
// SMS Response return delay: "a setting below 50 still defaults to 50 (100us)".
constexpr std::int64_t kSmsMinReturnDelay = 50;

// FEETECH's status error byte is the servo status (protocol-ft-scs.md: "If ERROR is 0, the
// servo has no alarm information"): it has no checksum, instruction or range bit, so a servo
// cannot say "no" with it. What it cannot make sense of (a bad checksum, an unknown or malformed
// instruction) and a read whose data it cannot send get no reply, which FEETECH's SDK reports as
// "There is no status packet!" (feetech/field-behaviour.md row 8, inferred). A write it refuses
// is acknowledged with error 0 (row 6, inferred: LeRobot raises on a missing reply or an error
// bit, yet its write of read-only address 85 succeeds on every SO-101). docs/feetech.md
// "Refusals".
constexpr Refusals kFeetechRefusals = {.checksum = wire::kSilentRefusal,
                                       .instruction = wire::kSilentRefusal,
                                       .read = wire::kSilentRefusal,
                                       .range = {.silent = false, .bit = 0}};

// Phase (18) bit 4, "angle feedback mode, (0) single-turn angle feedback, (1) full-angle
// feedback" (STS, SMS and HLS tables; SCSCL marks it unused).
constexpr std::uint8_t kFullAnglePhaseBit = 0x10;

// How FEETECH's protections act and end (feetech/field-behaviour.md row 7, after the STS3215
// specification): overload (Holding torque: "torque output after entering overload protection")
// and overcurrent (output off) until the next position command; over-voltage until the voltage
// recovers; over-temperature turns the torque off. FEETECH says nothing of the encoder: it keeps
// the Protocol 1.0 rule dxlemu gave it before, its unload lasting until Torque limit is written.
// FEETECH has no Hall sensor bit, so that rule is never used.
constexpr ErrorRules kFeetechErrorRules = {
    .input_voltage = {.effect = ErrorEffect::Unload, .end = ErrorEnd::Condition},
    .overheating = {.effect = ErrorEffect::TorqueOff, .end = ErrorEnd::Condition},
    .overload = {.effect = ErrorEffect::HoldingTorque, .end = ErrorEnd::PositionCommand},
    .electrical_shock = {.effect = ErrorEffect::Unload, .end = ErrorEnd::PositionCommand},
    .encoder = {.effect = ErrorEffect::Unload, .end = ErrorEnd::TorqueLimitWritten},
    .hall_sensor = {.effect = ErrorEffect::Unload, .end = ErrorEnd::TorqueLimitWritten}};

// SCS/SCSCL, the row the other FEETECH series start from (no Torque switch 128 in its table).
// The errors show in every status while they last and in Servo status; Unload condition selects
// the ones that act on the motor, each by its rule. A goal write turns torque on and torque on
// drives to the goal as it stands (docs/feetech.md "Motion").
constexpr FamilyTraits kScs = {.family = Family::Scs,
                               .name = "scs",
                               .maker = Maker::Feetech,
                               .drive = DriveKind::OperatingMode,
                               .goal_clamped_to_position_limits = true,
                               .torque_on_by_goal = TorqueOnByGoal::Always,
                               .torque_on_goal = TorqueOnGoal::MovesToGoal,
                               .torque_on_by_speed_goal = true,
                               .error_reaction = ErrorReaction::Unload,
                               .fault_bits = kScsFaultBits,
                               .error_rules = kFeetechErrorRules,
                               .reboot_status = false,
                               .operating_modes = kFeetechModes,
                               .mode_change_resets_goals = false,
                               .torque_limit_caps_torque = true,
                               .homing_offset_subtracts = true,
                               .secondary_id_addresses = false,
                               .status_level_all = 1,
                               .status_level_reads = 0,
                               .calibrated_position = kMiddlePosition,
                               .lock_flag_keeps_eeprom = true,
                               .refusals = kFeetechRefusals};

// STS: FEETECH's magnetic-encoder series (feetech/sts3215.md), with every status bit, Torque
// switch 128 and single-turn or full-angle feedback, whose turn count power-off loses.
constexpr FamilyTraits kSts = [] {
  FamilyTraits row = with_name(kScs, Family::Sts, "sts");
  row.fault_bits = kStsFaultBits;
  row.full_angle_phase_bit = kFullAnglePhaseBit;
  row.one_turn_at_boot = true;
  row.calibrate_torque_value = kTorqueCalibrate;
  return row;
}();

constexpr FamilyTraits kSms = [] {
  FamilyTraits row = with_name(kSts, Family::Sms, "sms");
  row.min_return_delay = kSmsMinReturnDelay;
  return row;
}();

// HLS: no load bit, no Torque switch 128 in its table.
constexpr FamilyTraits kHls = [] {
  FamilyTraits row = with_name(kScs, Family::Hls, "hls");
  row.fault_bits = kHlsFaultBits;
  row.full_angle_phase_bit = kFullAnglePhaseBit;
  row.one_turn_at_boot = true;
  return row;
}();

// In the order of `Family`: traits_of() indexes it.
constexpr std::array<FamilyTraits, 16> kFamilies = {
    kX,
    kMx2,
    kMx1,
    kAx,
    with_name(kAx, Family::Rx, "rx"),
    with_name(kAx, Family::Ex, "ex"),
    kXl320,
    kP,
    kPro,
    with_name(kAx, Family::Dx, "dx"),
    kProA,
    kY,
    kSts,
    kSms,
    kScs,
    kHls,
};

constexpr bool rows_in_family_order() {
  for (std::size_t i = 0; i < kFamilies.size(); ++i) {
    if (static_cast<std::size_t>(kFamilies[i].family) != i) {
      return false;
    }
  }
  return true;
}
static_assert(rows_in_family_order(), "kFamilies lists one row per Family, in enum order");

}  // namespace

wire::RefusalAnswer Refusals::of(wire::RefusalClass refusal_class) const {
  switch (refusal_class) {
    case wire::RefusalClass::None:
      return {};
    case wire::RefusalClass::Range:
      return range;
    case wire::RefusalClass::Instruction:
      return instruction;
    case wire::RefusalClass::Checksum:
      return checksum;
    case wire::RefusalClass::Read:
      return read;
  }
  return {};
}

const FamilyTraits& traits_of(Family family) {
  return kFamilies.at(static_cast<std::size_t>(family));
}

std::string_view family_name(Family family) {
  return traits_of(family).name;
}

std::optional<Family> family_from_name(std::string_view name) {
  for (const FamilyTraits& row : kFamilies) {
    if (row.name == name) {
      return row.family;
    }
  }
  return std::nullopt;
}

std::string family_names() {
  std::string out;
  for (const FamilyTraits& row : kFamilies) {
    out += out.empty() ? "" : ", ";
    out += row.name;
  }
  return out;
}

}  // namespace dxlemu::model
