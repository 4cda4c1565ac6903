// FEETECH's own instructions: status reset, parameter backup and recovery, position calibration
// (protocol-ft-scs.md 4.8 ~ 4.11; choices where it is silent in docs/feetech.md).
#include "model/servo.hpp"

namespace dxlemu::model {
namespace {

constexpr std::string_view kLockFlag = "lock_flag";
constexpr std::string_view kPositionOffset = "position_offset";

}  // namespace

bool Servo::feetech_eeprom_unlocked() const {
  const auto lock = spec().index_of(kLockFlag);
  return !lock || table_.get(*lock) == 0;
}

ServoResponse Servo::execute_feetech(const wire::StatusReset& /*reset*/) {
  // "Reset the servo status (reset the servo turn count)": the position back within one turn.
  ServoResponse r = from_table({}, write_time(0));
  motion_.clear_turns();
  return r;
}

ServoResponse Servo::execute_feetech(const wire::ParameterBackup& /*backup*/) {
  // "Unlock the eprom parameters before backing up": while locked nothing is stored, and the
  // status says so as a refused write does (no bit unless the model file sets one).
  if (!feetech_eeprom_unlocked()) {
    return respond(wire::Outcome::Access, write_time(0));
  }
  parameter_backup_ = std::vector<std::uint8_t>(table_.bytes().begin(), table_.bytes().end());
  return from_table({}, write_time(0));
}

ServoResponse Servo::execute_feetech(const wire::ParameterRecovery& /*recovery*/) {
  if (!feetech_eeprom_unlocked()) {
    return respond(wire::Outcome::Access, write_time(0));
  }
  ServoResponse r = from_table({}, write_time(0));
  // "Restore all servo parameters except the ID": the writable EEPROM items from the backup, or
  // from the factory values when nothing was backed up. A new baud rate applies after the status.
  for (std::size_t i = 0; i < spec().items.size(); ++i) {
    const ItemSpec& s = spec().items[i];
    if (s.area != Area::Eeprom || s.access != Access::ReadWrite || i == items_.id) {
      continue;
    }
    if (parameter_backup_) {
      table_.copy_from(i, *parameter_backup_);
    } else {
      table_.set(i, s.initial);
    }
    motion_.setting_forced(i);
  }
  return r;
}

ServoResponse Servo::execute_feetech(const wire::PositionCalibration& calibration) {
  // Only the models with a Position offset can calibrate (not SCS/SCSCL): to the others 0x0B is
  // an instruction their firmware does not have, refused as any unknown one.
  if (!spec().index_of(kPositionOffset)) {
    return respond(wire::Outcome::UnknownInstruction, write_time(0));
  }
  // No value: "calibrated to the middle position". A value the offset cannot reach changes
  // nothing and is refused as a value out of range is (no bit unless the model file sets one).
  const bool calibrated = motion_.calibrate_position(calibration.position.value_or(
      static_cast<std::uint16_t>(spec().traits().calibrated_position)));
  return respond(calibrated ? wire::Outcome::Ok : wire::Outcome::DataRange, write_time(0));
}

}  // namespace dxlemu::model
