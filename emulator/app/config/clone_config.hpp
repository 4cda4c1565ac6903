#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scan/bus_scan.hpp"

namespace dxlemu::app {

/// The bus config (docs/config.md) that serves the servos of `found` as the bus they were found
/// on: one port named `port_name` (with `link` unless it is empty), each servo of a known model
/// with its ID and the non-volatile items whose value differs from its factory one, raw, as the
/// control table holds them (Baud Rate and Protocol Type included). `source` names the bus in
/// the description. Servos of a model the library lacks are left out.
nlohmann::ordered_json clone_config(const std::vector<scan::FoundServo>& found,
                                    const std::string& source, const std::string& port_name,
                                    const std::string& link);

}  // namespace dxlemu::app
