#pragma once

#include "app/cli/command_line.hpp"

namespace dxlemu::app {

/// `dxlemu run`: builds the bus (--config, --robot, or --servo and --link), then serves it until
/// SIGINT, SIGTERM or the control API's shutdown, the readiness lines on stdout. `link_given`:
/// whether --link was on the command line (it has a default). Throws what Emulator and the
/// config readers throw (README.md "Running the emulator").
void serve(const CommandLine& line, bool link_given);

}  // namespace dxlemu::app
