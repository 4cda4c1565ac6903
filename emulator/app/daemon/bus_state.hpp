#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "model/table/control_table.hpp"

namespace dxlemu::app {

/// What a state file keeps of one servo: its model and the writable EEPROM items, by key (with
/// the saved values of the Hybrid items of DYNAMIXEL-Y).
struct ServoState {
  std::string model;
  std::vector<std::pair<std::string, std::int64_t>> eeprom;
  bool operator==(const ServoState&) const = default;
};

/// Every port's servos, by port name, in the port's bus order (docs/config.md "State file").
using BusState = std::map<std::string, std::vector<ServoState>>;

/// True for the items a servo keeps across power cycles, which a state file holds: writable
/// EEPROM, and the Hybrid area (DYNAMIXEL-Y), whose saved values a reboot restores.
bool is_non_volatile(const model::ItemSpec& item);

/// The writable EEPROM items of `table`, and the saved values of its Hybrid items.
ServoState capture_state(const model::ControlTable& table);

/// The bytes of every EEPROM item of `table` in address order, and the saved Hybrid values: a
/// cheap fingerprint to notice that non-volatile memory changed without building a ServoState.
std::vector<std::uint8_t> eeprom_image(const model::ControlTable& table);

/// Sets the EEPROM items of `state` in `table` (device side; Hybrid items: present and saved).
/// Throws ConfigError (origin, JSON pointer `at`) for an item the model does not have, a read-only
/// or RAM item, or a value outside the item's range; checks everything before setting anything.
void restore_state(model::ControlTable& table, const ServoState& state, const std::string& origin,
                   const std::string& at);

/// The JSON text of a state file.
std::string state_to_text(const BusState& state);

/// Parses a state file's text; throws ConfigError naming `origin`, the pointer and the reason.
BusState state_from_text(const std::string& text, const std::string& origin);

/// Reads `path`; an absent file is an empty state (first run). Throws ConfigError.
BusState read_state(const std::filesystem::path& path);

}  // namespace dxlemu::app
