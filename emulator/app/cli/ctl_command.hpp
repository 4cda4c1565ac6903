#pragma once

#include "app/cli/command_line.hpp"

namespace dxlemu::app {

/// `dxlemu ctl`: sends one request to a running emulator's control API and prints its reply.
/// Returns the exit status (docs/control-api.md "From a shell: dxlemu ctl"): 0 done, 1 the
/// daemon refused the request or failed to answer, 2 bad arguments or no daemon to talk to.
int run_ctl(const CtlArguments& ctl);

}  // namespace dxlemu::app
