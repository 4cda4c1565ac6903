#pragma once

#include "app/cli/command_line.hpp"

namespace dxlemu::app {

/// `dxlemu robots`: one line per robot profile (shipped and --robots), by name, with its ports,
/// servos, whether a physics file of that name ships, its role in a leader and follower pair,
/// its title and first source; then each pair with the command that serves both
/// (docs/robots.md). None is not an error: stderr says so.
void list_robots(const CommandLine& line);

}  // namespace dxlemu::app
