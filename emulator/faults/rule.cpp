#include "faults/rule.hpp"

#include <array>

namespace dxlemu::faults {

namespace {

struct Named {
  Action action;
  std::string_view name;
};

constexpr std::array<Named, 17> kNames{{
    {Action::DropReply, "drop_reply"},
    {Action::DelayReply, "delay_reply"},
    {Action::CorruptCrc, "corrupt_crc"},
    {Action::FlipBits, "flip_bits"},
    {Action::TruncateReply, "truncate_reply"},
    {Action::GarbageBefore, "garbage_before"},
    {Action::DuplicateReply, "duplicate_reply"},
    {Action::WrongId, "wrong_id"},
    {Action::EchoInstruction, "echo_instruction"},
    {Action::Noise, "noise"},
    {Action::CorruptInstruction, "corrupt_instruction"},
    {Action::HardwareError, "hardware_error"},
    {Action::Silence, "silence"},
    {Action::SilenceUntilReboot, "silence_until_reboot"},
    {Action::Slow, "slow"},
    {Action::EepromBusy, "eeprom_busy"},
    {Action::ModbusException, "modbus_exception"},
}};

}  // namespace

std::string_view action_name(Action action) {
  for (const Named& n : kNames) {
    if (n.action == action) {
      return n.name;
    }
  }
  return "unknown";
}

std::optional<Action> action_from_name(std::string_view name) {
  for (const Named& n : kNames) {
    if (n.name == name) {
      return n.action;
    }
  }
  return std::nullopt;
}

const std::vector<Action>& all_actions() {
  static const std::vector<Action> actions = [] {
    std::vector<Action> out;
    out.reserve(kNames.size());
    for (const Named& n : kNames) {
      out.push_back(n.action);
    }
    return out;
  }();
  return actions;
}

}  // namespace dxlemu::faults
