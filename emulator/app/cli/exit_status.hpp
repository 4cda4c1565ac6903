#pragma once

#include <functional>

namespace dxlemu::app {

/// Exit status for refused input (bad option, model file or config), as documented in README.md.
inline constexpr int kExitBadInput = 2;
/// `dxlemu exec`'s own failures (docs/exec.md), apart from COMMAND's statuses as env(1) does.
inline constexpr int kExitExecFailed = 125;

/// Runs a subcommand's `body` and turns its failures into the documented exit statuses, with the
/// message on stderr: 2 for refused input (bad option, model or config: std::invalid_argument,
/// model::ModelError), 1 for anything else (e.g. no pseudo-terminal available); 0 when it returns.
int exit_status_of(const std::function<void()>& body);

}  // namespace dxlemu::app
