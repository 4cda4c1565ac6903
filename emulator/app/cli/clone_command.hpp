#pragma once

#include <iosfwd>

#include "app/cli/command_line.hpp"
#include "app/config/model_library.hpp"

namespace dxlemu::app {

/// `dxlemu clone PORT`: scans the bus on the serial device (Ping and Read only), writes the
/// config that serves it to --out (atomically) or `out`, progress to `progress`. Throws
/// std::invalid_argument for bad arguments, std::runtime_error when no servo answered,
/// std::system_error when the device cannot be used (docs/robots.md "Cloning a real bus").
void clone_bus(const CloneArguments& arguments, const ModelLibrary& library, std::ostream& out,
               std::ostream& progress);

}  // namespace dxlemu::app
