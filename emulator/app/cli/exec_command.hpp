#pragma once

#include "app/cli/exec_setup.hpp"

namespace dxlemu::app {

/// `dxlemu exec`: runs COMMAND with LD_PRELOAD and DXLEMU_PTYS set so that the emulator's PTYs
/// behave like a USB adapter. Returns COMMAND's exit status as env(1) does, kExitExecFailed when
/// it cannot be started (docs/exec.md).
int run_exec(const ExecArguments& arguments);

}  // namespace dxlemu::app
