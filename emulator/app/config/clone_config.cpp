#include "app/config/clone_config.hpp"

namespace dxlemu::app {

nlohmann::ordered_json clone_config(const std::vector<scan::FoundServo>& found,
                                    const std::string& source, const std::string& port_name,
                                    const std::string& link) {
  nlohmann::ordered_json servos = nlohmann::ordered_json::array();
  for (const scan::FoundServo& servo : found) {
    if (!servo.spec) {
      continue;
    }
    const model::ModelSpec& spec = *servo.spec;
    nlohmann::ordered_json items = nlohmann::ordered_json::object();
    for (const auto& [key, value] : servo.eeprom) {
      // The ID is the servo's own field; a factory value needs no override.
      const auto index = spec.index_of(key);
      if (key != "id" && index && spec.items[*index].initial != value) {
        items[key] = value;
      }
    }
    nlohmann::ordered_json entry;
    entry["model"] = spec.name;
    entry["id"] = servo.id;
    entry["description"] = "found at " + std::to_string(servo.bps) + " bps, " +
                           std::string(wire::protocol_title(servo.protocol)) + ", model number " +
                           std::to_string(servo.model_number) + ", firmware " +
                           std::to_string(servo.firmware);
    if (!items.empty()) {
      entry["items"] = std::move(items);
    }
    servos.push_back(std::move(entry));
  }
  nlohmann::ordered_json port;
  port["name"] = port_name;
  if (!link.empty()) {
    port["link"] = link;
  }
  port["servos"] = std::move(servos);
  nlohmann::ordered_json config;
  config["description"] = "cloned from " + source + " by dxlemu clone";
  config["ports"] = nlohmann::ordered_json::array({std::move(port)});
  return config;
}

}  // namespace dxlemu::app
