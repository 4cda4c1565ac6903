#include "app/config/bus_options.hpp"

#include <exception>
#include <stdexcept>
#include <utility>

namespace dxlemu::app {

std::vector<ServoConfig> parse_servo_option(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    throw std::invalid_argument("--servo " + text + ": expected NAME:ID or NAME:FIRST-LAST");
  }
  const std::string name = text.substr(0, colon);
  const std::string ids = text.substr(colon + 1);
  const auto dash = ids.find('-');
  int first = 0;
  int last = 0;
  try {
    std::size_t used = 0;
    first = std::stoi(ids.substr(0, dash), &used);
    if (used != ids.substr(0, dash).size()) {
      throw std::invalid_argument("");
    }
    last = first;
    if (dash != std::string::npos) {
      last = std::stoi(ids.substr(dash + 1), &used);
      if (used != ids.substr(dash + 1).size()) {
        throw std::invalid_argument("");
      }
    }
  } catch (const std::exception&) {
    throw std::invalid_argument("--servo " + text + ": the ID part must be a number or FIRST-LAST");
  }
  if (first < 0 || last > kMaxServoId || first > last) {
    throw std::invalid_argument("--servo " + text + ": IDs must lie in 0 ~ 252, first <= last");
  }
  std::vector<ServoConfig> out;
  for (int id = first; id <= last; ++id) {
    out.push_back({name, static_cast<std::uint8_t>(id), {}});
  }
  return out;
}

void apply_bus_options(BusConfig& config, const ModelLibrary& library,
                       std::optional<std::uint32_t> baud, std::optional<wire::Protocol> protocol) {
  for (auto& port : config.ports) {
    for (auto& servo : port.servos) {
      const auto spec = library.find(servo.model);
      if (!spec) {
        continue;  // check_servo names it
      }
      try {
        if (baud) {
          servo.items.emplace_back("baud_rate", baud_rate_item_value(*spec, *baud));
        }
        if (protocol) {
          if (auto item = protocol_item(*spec, *protocol, library)) {
            servo.items.push_back(std::move(*item));
          }
        }
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(baud ? "--baud" : "--protocol") +
                                    (baud && protocol ? "/--protocol" : "") + ": " + e.what());
      }
      if (protocol) {
        // The IDs of a port given with --servo or a config may not all be IDs of the protocol
        // asked for (Modbus RTU: 1 ~ 247).
        try {
          check_servo_id(servo, *spec);
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument(
              "--protocol " + std::string(wire::traits(*protocol).spelling) + ": " + e.what());
        }
      }
    }
  }
}

}  // namespace dxlemu::app
