#pragma once

#include "app/cli/command_line.hpp"

namespace dxlemu::app {

/// `dxlemu check FILE` or `check --robot NAME`: validates a config or a robot profile (with
/// --physics, that its MJCF loads and names every joint) and prints its ports. Throws
/// ConfigError or model::ModelError for what it refuses (docs/config.md).
void check_config(const CommandLine& line);

}  // namespace dxlemu::app
