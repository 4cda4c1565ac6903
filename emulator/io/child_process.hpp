#pragma once

#include <map>
#include <string>
#include <vector>

namespace dxlemu::io {

/// Exit statuses of `dxlemu exec` itself, as env(1) and timeout(1) have them (docs/exec.md).
inline constexpr int kExitCannotExecute = 126;  ///< COMMAND found but could not be run
inline constexpr int kExitNotFound = 127;       ///< COMMAND not found
inline constexpr int kExitSignalBase = 128;     ///< plus the signal that killed COMMAND

/// Runs `command` (searched in $PATH like execvp) with this process's environment changed by
/// `environment` (name -> value), waits for it and returns its exit status, or kExitSignalBase
/// plus the signal that killed it. While it runs, SIGTERM, SIGHUP, SIGINT and SIGQUIT sent to
/// this process by kill(2) are passed on to it; those a terminal sends reach it directly (it is
/// in the same process group), so they are not sent twice. When `command` cannot be started,
/// prints why on stderr and returns kExitNotFound or kExitCannotExecute.
int run_child(const std::vector<std::string>& command,
              const std::map<std::string, std::string>& environment);

}  // namespace dxlemu::io
