#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "model/spec/model_loader.hpp"

namespace dxlemu::test {

/// A small X-like model exercising every kind of item rule, for tests that must not depend on the
/// shipped model files: EEPROM and RAM, read-only, signed, values, limits (plain and negated),
/// initial_from, reserved gaps, one Indirect block of 4 entries.
inline nlohmann::json test_model_json() {
  return nlohmann::json::parse(R"({
    "name": "test-x", "title": "TEST-X", "model_number": 4242, "firmware_version": 46,
    "family": "x", "protocols": [2, 1], "default_id": 1,
    "baud_rates": [{"index": 0, "bps": 9600}, {"index": 1, "bps": 57600}, {"index": 3, "bps": 1000000}],
    "default_baud_index": 1, "return_delay_unit_us": 2,
    "timing": {"ping_us": 50, "read_us": 50, "write_us": 50, "write_per_byte_us": 0, "boot_ms": 100},
    "motion": {"degrees_per_pulse": 0.087890625, "velocity_unit_rpm": 0.229},
    "indirect": [{"address": 40, "data": 50, "count": 4}],
    "source": "unit test",
    "items": [
      {"key": "model_number", "name": "Model Number", "address": 0, "size": 2, "access": "R", "area": "EEPROM", "initial": 4242},
      {"key": "id", "name": "ID", "address": 7, "size": 1, "access": "RW", "area": "EEPROM", "initial": 1, "min": 0, "max": 252},
      {"key": "operating_mode", "name": "Operating Mode", "address": 11, "size": 1, "access": "RW", "area": "EEPROM", "initial": 3, "values": [0, 1, 3, 4, 5, 16]},
      {"key": "pwm_limit", "name": "PWM Limit", "address": 12, "size": 2, "access": "RW", "area": "EEPROM", "initial": 885, "min": 0, "max": 885},
      {"key": "max_position_limit", "name": "Max Position Limit", "address": 16, "size": 4, "access": "RW", "area": "EEPROM", "initial": 4095, "min": 0, "max": 4095},
      {"key": "min_position_limit", "name": "Min Position Limit", "address": 20, "size": 4, "access": "RW", "area": "EEPROM", "initial": 0, "min": 0, "max": 4095},
      {"key": "torque_enable", "name": "Torque Enable", "address": 24, "size": 1, "access": "RW", "area": "RAM", "initial": 0, "min": 0, "max": 1},
      {"key": "goal_pwm", "name": "Goal PWM", "address": 26, "size": 2, "access": "RW", "area": "RAM", "initial_from": "pwm_limit", "signed": true, "min": -885, "max": 885, "limit_min": "-pwm_limit", "limit_max": "pwm_limit"},
      {"key": "goal_position", "name": "Goal Position", "address": 28, "size": 4, "access": "RW", "area": "RAM", "initial": 2048, "min": 0, "max": 4095, "limit_min": "min_position_limit", "limit_max": "max_position_limit"},
      {"key": "present_velocity", "name": "Present Velocity", "address": 32, "size": 4, "access": "R", "area": "RAM", "initial": -5, "signed": true},
      {"key": "indirect_address_1", "name": "Indirect Address 1", "address": 40, "size": 2, "access": "RW", "area": "RAM", "initial": 50, "min": 24, "max": 59},
      {"key": "indirect_address_2", "name": "Indirect Address 2", "address": 42, "size": 2, "access": "RW", "area": "RAM", "initial": 51, "min": 24, "max": 59},
      {"key": "indirect_address_3", "name": "Indirect Address 3", "address": 44, "size": 2, "access": "RW", "area": "RAM", "initial": 52, "min": 24, "max": 59},
      {"key": "indirect_address_4", "name": "Indirect Address 4", "address": 46, "size": 2, "access": "RW", "area": "RAM", "initial": 53, "min": 24, "max": 59},
      {"key": "indirect_data_1", "name": "Indirect Data 1", "address": 50, "size": 1, "access": "RW", "area": "RAM", "initial": 0},
      {"key": "indirect_data_2", "name": "Indirect Data 2", "address": 51, "size": 1, "access": "RW", "area": "RAM", "initial": 0},
      {"key": "indirect_data_3", "name": "Indirect Data 3", "address": 52, "size": 1, "access": "RW", "area": "RAM", "initial": 0},
      {"key": "indirect_data_4", "name": "Indirect Data 4", "address": 53, "size": 1, "access": "RW", "area": "RAM", "initial": 0},
      {"key": "present_temperature", "name": "Present Temperature", "address": 59, "size": 1, "access": "R", "area": "RAM", "initial": 25},
      {"key": "baud_rate", "name": "Baud Rate", "address": 8, "size": 1, "access": "RW", "area": "EEPROM", "initial": 1, "values": [0, 1, 3]},
      {"key": "return_delay_time", "name": "Return Delay Time", "address": 9, "size": 1, "access": "RW", "area": "EEPROM", "initial": 250, "min": 0, "max": 254}
    ]
  })");
}

/// The item with `key` of a model document, to change it before loading. Throws
/// std::logic_error when there is none.
inline nlohmann::json& item_json(nlohmann::json& model, const std::string& key) {
  for (nlohmann::json& i : model["items"]) {
    if (i["key"] == key) {
      return i;
    }
  }
  throw std::logic_error("no item " + key);
}

/// The test model as a ModelSpec.
inline std::shared_ptr<const model::ModelSpec> test_model(
    const nlohmann::json& document = test_model_json()) {
  return std::make_shared<const model::ModelSpec>(model::model_from_json(document, "test-x.json"));
}

}  // namespace dxlemu::test
