// The table of family traits (model/spec/family_traits.hpp): one row per family, found by its name,
// saying what the e-Manual says each family does beyond its control table.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "model/motion/hardware_fault.hpp"
#include "model/spec/family_traits.hpp"

using namespace dxlemu;
using model::Family;
using model::traits_of;

namespace {

const std::vector<std::pair<Family, std::string>> kNames = {
    {Family::X, "x"},     {Family::Mx2, "mx2"}, {Family::Mx1, "mx1"},     {Family::Ax, "ax"},
    {Family::Rx, "rx"},   {Family::Ex, "ex"},   {Family::Xl320, "xl320"}, {Family::P, "p"},
    {Family::Pro, "pro"}, {Family::Dx, "dx"},   {Family::ProA, "pro_a"},  {Family::Y, "y"},
    {Family::Sts, "sts"}, {Family::Sms, "sms"}, {Family::Scs, "scs"},     {Family::Hls, "hls"}};

bool same_bits(const model::FaultBits& a, const model::FaultBits& b) {
  return a.input_voltage == b.input_voltage && a.overheating == b.overheating &&
         a.overload == b.overload && a.electrical_shock == b.electrical_shock &&
         a.encoder == b.encoder && a.hall_sensor == b.hall_sensor;
}

}  // namespace

TEST_CASE("Every family has one row, found by its name in model files", "[model][traits]") {
  for (const auto& [family, name] : kNames) {
    CAPTURE(name);
    CHECK(traits_of(family).family == family);
    CHECK(model::family_name(family) == name);
    CHECK(model::family_from_name(name) == family);
  }
  CHECK(model::family_names() ==
        "x, mx2, mx1, ax, rx, ex, xl320, p, pro, dx, pro_a, y, sts, sms, scs, hls");
  CHECK_FALSE(model::family_from_name("pro+").has_value());
}

TEST_CASE("The Protocol 1.0 families move by joint and wheel mode and shut down by alarm",
          "[model][traits]") {
  for (const Family family : {Family::Ax, Family::Rx, Family::Ex, Family::Dx, Family::Mx1}) {
    CAPTURE(model::family_name(family));
    const model::FamilyTraits& t = traits_of(family);
    CHECK(t.drive == model::DriveKind::JointWheel);
    CHECK(t.goal_within_angle_limits);
    CHECK_FALSE(t.eeprom_locked_by_torque);  // they lock EEPROM through Lock
    CHECK(t.torque_on_by_goal == model::TorqueOnByGoal::Always);
    CHECK(t.torque_on_goal == model::TorqueOnGoal::MovesToGoal);
    CHECK_FALSE(t.one_turn_at_boot);
    CHECK_FALSE(t.one_turn_at_torque_on);
    CHECK_FALSE(t.drive_mode_reverses);
    CHECK(t.error_reaction == model::ErrorReaction::AlarmShutdown);
    CHECK(same_bits(t.fault_bits, model::kProtocol1FaultBits));
    CHECK(t.protocol1_firmware);
  }
  CHECK(traits_of(Family::Mx1).multi_turn_angle_limit == 4095);
  CHECK_FALSE(traits_of(Family::Ax).multi_turn_angle_limit.has_value());
  // protocol1.md "Reboot": MX (v40+) knows it, AX, RX, EX (and DX, of their generation) do not.
  CHECK(traits_of(Family::Mx1).reboot);
  for (const Family family : {Family::Ax, Family::Rx, Family::Ex, Family::Dx}) {
    CHECK_FALSE(traits_of(family).reboot);
  }
  for (const Family family :
       {Family::X, Family::Mx2, Family::Xl320, Family::P, Family::Pro, Family::ProA, Family::Y}) {
    CHECK(traits_of(family).reboot);
  }
}

TEST_CASE("XL-320 moves like a 1.0 family but latches its errors in its own Shutdown bits",
          "[model][traits]") {
  const model::FamilyTraits& t = traits_of(Family::Xl320);
  CHECK(t.drive == model::DriveKind::JointWheel);
  CHECK(t.goal_within_angle_limits);
  CHECK(t.eeprom_locked_by_torque);
  CHECK(t.torque_on_by_goal == model::TorqueOnByGoal::Never);
  CHECK(t.error_reaction == model::ErrorReaction::LatchedShutdown);
  CHECK(model::fault_bit(Family::Xl320, model::HardwareFault::Overload) == 0x01);
  CHECK(model::fault_bit(Family::Xl320, model::HardwareFault::Overheating) == 0x02);
  CHECK(model::fault_bit(Family::Xl320, model::HardwareFault::InputVoltage) == 0x04);
  CHECK_FALSE(t.protocol1_firmware);
}

TEST_CASE("The Operating Mode families hold at torque on and latch their errors",
          "[model][traits]") {
  for (const Family family : {Family::X, Family::Mx2, Family::P, Family::Pro, Family::ProA}) {
    CAPTURE(model::family_name(family));
    const model::FamilyTraits& t = traits_of(family);
    CHECK(t.drive == model::DriveKind::OperatingMode);
    CHECK_FALSE(t.goal_within_angle_limits);
    CHECK(t.eeprom_locked_by_torque);
    CHECK(t.torque_on_by_goal == model::TorqueOnByGoal::DriveModeBit);
    CHECK(t.torque_on_goal == model::TorqueOnGoal::Holds);
    CHECK(t.one_turn_at_boot);
    CHECK(t.one_turn_at_torque_on);
    CHECK(t.error_reaction == model::ErrorReaction::LatchedShutdown);
    CHECK_FALSE(t.protocol1_firmware);
  }
  CHECK(traits_of(Family::X).extended_goals == model::ExtendedGoals::Turns);
  CHECK(traits_of(Family::Mx2).extended_goals == model::ExtendedGoals::Turns);
  CHECK(traits_of(Family::P).extended_goals == model::ExtendedGoals::ItemWidth);
  CHECK(traits_of(Family::ProA).extended_goals == model::ExtendedGoals::ItemWidth);  // P firmware
  CHECK(traits_of(Family::Pro).extended_goals == model::ExtendedGoals::ItemRange);
  CHECK_FALSE(traits_of(Family::Pro).drive_mode_reverses);  // PRO has no Drive Mode
  // Only P, PRO and PRO(A) report the Hall sensor.
  CHECK(model::fault_bit(Family::P, model::HardwareFault::HallSensor) == 0x02);
  CHECK(model::fault_bit(Family::ProA, model::HardwareFault::HallSensor) == 0x02);
  CHECK(model::fault_bit(Family::Pro, model::HardwareFault::HallSensor) == 0x02);
  CHECK(model::fault_bit(Family::X, model::HardwareFault::HallSensor) == 0);
}

TEST_CASE(
    "DYNAMIXEL-Y follows P where its pages are silent, with Error Code and Moving Status bits",
    "[model][traits]") {
  const model::FamilyTraits& t = traits_of(Family::Y);
  CHECK(t.drive == model::DriveKind::OperatingMode);
  CHECK(t.eeprom_locked_by_torque);  // "Setting the value to '1' ... prevents writing ... EEPROM"
  CHECK(t.drive_mode_reverses);      // Drive Mode bit 0 Normal/Reverse Mode
  CHECK(t.torque_on_goal == model::TorqueOnGoal::Holds);
  // No Torque On by Goal Update bit (Drive Mode bit 3 "Unused"), no extended position mode, and a
  // multi-turn position the servo keeps over power cycles.
  CHECK(t.torque_on_by_goal == model::TorqueOnByGoal::Never);
  CHECK(t.extended_goals == model::ExtendedGoals::ItemRange);
  CHECK_FALSE(t.one_turn_at_boot);
  CHECK_FALSE(t.one_turn_at_torque_on);
  CHECK(t.error_reaction == model::ErrorReaction::ErrorCode);
  CHECK(t.error_codes.over_voltage == 1);
  CHECK(t.error_codes.low_voltage == 2);
  CHECK(t.error_codes.overheating == 4);
  CHECK(t.error_codes.overload == 5);
  CHECK(t.error_codes.encoder == 13);
  CHECK(t.error_codes.hall_sensor == 14);
  CHECK(t.error_codes.bus_watchdog == 18);
  CHECK(same_bits(t.fault_bits, {}));  // no Shutdown / Hardware Error Status items
  CHECK(t.moving_status_motion_and_range);
  for (const auto& [family, name] : kNames) {
    CAPTURE(name);
    CHECK(traits_of(family).moving_status_motion_and_range == (family == Family::Y));
    CHECK((traits_of(family).error_reaction == model::ErrorReaction::ErrorCode) ==
          (family == Family::Y));
  }
}

TEST_CASE(
    "Fast Sync/Bulk Read and the 1.0 Bulk Read are for the families protocol2.md and "
    "protocol1.md name",
    "[model][traits]") {
  for (const auto& [family, name] : kNames) {
    CAPTURE(name);
    const model::FamilyTraits& t = traits_of(family);
    const auto fast = family == Family::X   ? model::FastRead::SingleAxis
                      : family == Family::P ? model::FastRead::All
                                            : model::FastRead::None;
    CHECK(t.fast_read == fast);
    CHECK(t.v1_bulk_read ==
          (family == Family::Mx1 || family == Family::Mx2 || family == Family::X));
  }
}

TEST_CASE("The FEETECH series: FEETECH's status bits, mode values, response levels and Lock",
          "[model][traits][feetech]") {
  using model::HardwareFault;
  for (const Family family : {Family::Sts, Family::Sms, Family::Scs, Family::Hls}) {
    CAPTURE(model::family_name(family));
    const model::FamilyTraits& t = traits_of(family);
    CHECK(t.maker == model::Maker::Feetech);
    CHECK(t.drive == model::DriveKind::OperatingMode);
    CHECK(t.error_reaction == model::ErrorReaction::Unload);
    // feetech/field-behaviour.md row 7: what each protection does and when it ends.
    const model::ErrorRules& r = t.error_rules;
    CHECK((r.overload.effect == model::ErrorEffect::HoldingTorque &&
           r.overload.end == model::ErrorEnd::PositionCommand));
    CHECK((r.electrical_shock.effect == model::ErrorEffect::Unload &&
           r.electrical_shock.end == model::ErrorEnd::PositionCommand));
    CHECK((r.input_voltage.effect == model::ErrorEffect::Unload &&
           r.input_voltage.end == model::ErrorEnd::Condition));
    CHECK((r.overheating.effect == model::ErrorEffect::TorqueOff &&
           r.overheating.end == model::ErrorEnd::Condition));
    CHECK(r.encoder.end == model::ErrorEnd::TorqueLimitWritten);
    CHECK_FALSE(t.reboot_status);  // Restart: "status frame: none"
    CHECK(t.operating_modes.position == 0);
    CHECK(t.operating_modes.velocity == 1);
    CHECK(t.operating_modes.pwm == 2);
    CHECK_FALSE(t.operating_modes.current.has_value());
    CHECK(t.homing_offset_subtracts);
    CHECK_FALSE(t.secondary_id_addresses);
    CHECK((t.status_level_all == 1 && t.status_level_reads == 0));
    CHECK(t.lock_flag_keeps_eeprom);
    CHECK_FALSE(t.eeprom_locked_by_torque);
    // No error bit to say "no": silence where the servo cannot act on the packet or send the
    // data, an acknowledgement with no bit for a refused write.
    CHECK(t.refusals == model::Refusals{.checksum = wire::kSilentRefusal,
                                        .instruction = wire::kSilentRefusal,
                                        .read = wire::kSilentRefusal,
                                        .range = {}});
    CHECK(model::fault_bit(family, HardwareFault::InputVoltage) == 0x01);
    CHECK(model::fault_bit(family, HardwareFault::Overheating) == 0x04);
  }
  CHECK(model::fault_bit(Family::Sts, HardwareFault::Encoder) == 0x02);
  CHECK(model::fault_bit(Family::Sts, HardwareFault::ElectricalShock) == 0x08);
  CHECK(model::fault_bit(Family::Sts, HardwareFault::Overload) == 0x20);
  CHECK(model::fault_bit(Family::Scs, HardwareFault::Encoder) == 0);
  CHECK(model::fault_bit(Family::Hls, HardwareFault::Overload) == 0);
  CHECK(traits_of(Family::Sms).min_return_delay == 50);
  CHECK(traits_of(Family::Sts).min_return_delay == 0);
  CHECK(traits_of(Family::Sts).calibrate_torque_value == 128);
  CHECK_FALSE(traits_of(Family::Scs).calibrate_torque_value.has_value());
  for (const auto& [family, name] : kNames) {
    const bool feetech = name == "sts" || name == "sms" || name == "scs" || name == "hls";
    CHECK((traits_of(family).maker == model::Maker::Feetech) == feetech);
  }
}
