#include "app/daemon/bus_state.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/config/bus_config.hpp"

namespace dxlemu::app {
namespace {

using nlohmann::ordered_json;

constexpr const char* kFormat = "dxlemu-state";
constexpr int kVersion = 1;

}  // namespace

bool is_non_volatile(const model::ItemSpec& item) {
  return (item.area == model::Area::Eeprom || item.area == model::Area::Hybrid) &&
         item.access == model::Access::ReadWrite;
}

ServoState capture_state(const model::ControlTable& table) {
  ServoState state{table.spec().name, {}};
  for (std::size_t i = 0; i < table.spec().items.size(); ++i) {
    const model::ItemSpec& item = table.spec().items[i];
    if (is_non_volatile(item)) {
      // What a power cycle would bring back: Hybrid items' saved values, FEETECH EEPROM items'
      // last value written while the Lock flag was 0.
      state.eeprom.emplace_back(item.key, table.kept_value(i));
    }
  }
  return state;
}

std::vector<std::uint8_t> eeprom_image(const model::ControlTable& table) {
  std::vector<std::uint8_t> out;
  const auto bytes = table.bytes();
  for (std::size_t i = 0; i < table.spec().items.size(); ++i) {
    const model::ItemSpec& item = table.spec().items[i];
    if (item.area == model::Area::Eeprom) {
      out.insert(out.end(), bytes.begin() + item.address, bytes.begin() + item.address + item.size);
    }
    if (item.area == model::Area::Hybrid || item.area == model::Area::Eeprom) {
      // The kept value too: unsaved Hybrid writes and FEETECH EEPROM writes made while locked
      // are lost at power-off.
      const auto saved = static_cast<std::uint64_t>(table.kept_value(i));
      for (int b = 0; b < 8; ++b) {
        out.push_back(static_cast<std::uint8_t>(saved >> (8 * b)));
      }
    }
  }
  return out;
}

void restore_state(model::ControlTable& table, const ServoState& state, const std::string& origin,
                   const std::string& at) {
  for (const auto& [key, value] : state.eeprom) {
    const model::ItemSpec* item = table.spec().find(key);
    const std::string item_at = at + "/eeprom/" + key;
    if (item == nullptr) {
      throw ConfigError(origin, item_at, state.model + " has no item \"" + key + "\"");
    }
    if (!is_non_volatile(*item)) {
      throw ConfigError(origin, item_at, "is not a writable EEPROM item");
    }
    if (!item->in_range(value)) {
      throw ConfigError(origin, item_at,
                        std::to_string(value) + " is outside the item's range " +
                            std::to_string(item->min) + " ~ " + std::to_string(item->max));
    }
  }
  for (const auto& [key, value] : state.eeprom) {
    const std::size_t item = table.index(key);
    table.restore_kept(item, value);
  }
}

std::string state_to_text(const BusState& state) {
  ordered_json ports = ordered_json::object();
  for (const auto& [name, servos] : state) {
    ordered_json list = ordered_json::array();
    for (const ServoState& servo : servos) {
      ordered_json eeprom = ordered_json::object();
      for (const auto& [key, value] : servo.eeprom) {
        eeprom[key] = value;
      }
      list.push_back({{"model", servo.model}, {"eeprom", eeprom}});
    }
    ports[name] = list;
  }
  const ordered_json doc = {{"format", kFormat}, {"version", kVersion}, {"ports", ports}};
  return doc.dump(2) + "\n";
}

BusState state_from_text(const std::string& text, const std::string& origin) {
  ordered_json doc;
  try {
    doc = ordered_json::parse(text);
  } catch (const ordered_json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    throw ConfigError(origin, "", std::string("not valid JSON: ") + e.what());
  }
  auto fail = [&](const std::string& at, const std::string& reason) {
    throw ConfigError(origin, at, reason);
  };
  if (!doc.is_object()) {
    fail("", "must be an object");
  }
  if (!doc.contains("format") || doc["format"] != kFormat) {
    fail("/format", std::string("must be \"") + kFormat + "\" (is this a dxlemu state file?)");
  }
  if (!doc.contains("version") || doc["version"] != kVersion) {
    fail("/version", "must be " + std::to_string(kVersion));
  }
  if (!doc.contains("ports") || !doc["ports"].is_object()) {
    fail("/ports", "must be an object of port names");
  }
  BusState state;
  const ordered_json& ports = doc["ports"];
  for (const auto& [name, servos] : ports.items()) {
    const std::string port_at = "/ports/" + name;
    if (!servos.is_array()) {
      fail(port_at, "must be an array of servos");
    }
    auto& list = state[name];
    for (std::size_t i = 0; i < servos.size(); ++i) {
      const std::string at = port_at + "/" + std::to_string(i);
      const ordered_json& s = servos[i];
      if (!s.is_object() || !s.contains("model") || !s["model"].is_string()) {
        fail(at + "/model", "must be a string");
      }
      if (!s.contains("eeprom") || !s["eeprom"].is_object()) {
        fail(at + "/eeprom", "must be an object of item keys and values");
      }
      ServoState servo{s["model"].get<std::string>(), {}};
      for (const auto& [key, value] : s["eeprom"].items()) {
        if (!value.is_number_integer()) {
          fail(at + "/eeprom/" + key, "must be an integer");
        }
        servo.eeprom.emplace_back(key, value.get<std::int64_t>());
      }
      list.push_back(std::move(servo));
    }
  }
  return state;
}

BusState read_state(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (!std::filesystem::exists(path)) {
      return {};
    }
    throw ConfigError(path.string(), "", "cannot be read");
  }
  std::stringstream text;
  text << in.rdbuf();
  return state_from_text(text.str(), path.string());
}

}  // namespace dxlemu::app
