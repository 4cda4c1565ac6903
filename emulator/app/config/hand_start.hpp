#pragma once

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "app/config/bus_config.hpp"

namespace dxlemu::app {

/// The hand of `--hand SPEC` (docs/hands.md "From the command line"): "sweep" or a trajectory
/// (a file, or a shipped trajectory's name), then options as ",KEY=VALUE" (a value is read as
/// JSON when it parses, else as text) or ",KEY" for true: `pick.csv,loop,speed=2`,
/// `sweep,order=together`. The options are the hand.sweep or hand.play request's arguments,
/// which the control API checks when the daemon starts. Throws std::invalid_argument for an
/// empty SPEC or KEY.
HandStart hand_start_of_option(const std::string& spec);

/// The hands of a config port's "hand" at `pointer` of file `origin`: a SPEC string as for
/// --hand, an object `{"file": FILE, ...}` or `{"sweep": true, ...}` whose other members are
/// the request's arguments, or an array of these. A relative FILE is read from `folder` (the
/// config's) when a file is there. Throws ConfigError naming the pointer.
std::vector<HandStart> hand_starts_of_json(const nlohmann::json& value, const std::string& origin,
                                           const std::string& pointer,
                                           const std::filesystem::path& folder);

}  // namespace dxlemu::app
