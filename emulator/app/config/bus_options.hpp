#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"

namespace dxlemu::app {

/// The servos of one `--servo` option of `dxlemu run`: "NAME:ID" or "NAME:FIRST-LAST", at factory
/// settings. NAME may carry a firmware, "xl330-m288@52", which the library resolves later (model
/// names hold no ':', though they may hold other punctuation such as '+'). Throws
/// std::invalid_argument naming the option for a malformed one or IDs outside 0 ~ 252.
std::vector<ServoConfig> parse_servo_option(const std::string& text);

/// Applies `dxlemu run`'s --baud and --protocol to every servo of `config`, after its own item
/// overrides (so they win). A servo whose model `library` does not know is left for check_servo()
/// to name. Throws std::invalid_argument naming the options when a model has no such baud rate or
/// cannot speak the protocol (naming the models that can), or a servo's ID is not one of the
/// protocol's (Modbus RTU: 1 ~ 247).
void apply_bus_options(BusConfig& config, const ModelLibrary& library,
                       std::optional<std::uint32_t> baud, std::optional<wire::Protocol> protocol);

}  // namespace dxlemu::app
