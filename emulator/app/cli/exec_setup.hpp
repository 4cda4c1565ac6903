#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/ctl_request.hpp"

namespace dxlemu::app {

/// `dxlemu exec`'s arguments (docs/exec.md).
struct ExecArguments {
  std::vector<std::string> ports;               ///< --port, as given
  std::vector<std::filesystem::path> controls;  ///< --control, as given
  std::vector<std::string> command;             ///< COMMAND and its arguments (exec_command)
};

/// The file name of the preload library (docs/exec.md).
inline constexpr const char* kPreloadLibraryName = "libdxlemu-preload.so";

/// True when a path names a character device (links followed): a PTY or a link to one.
using CharacterDeviceTest = std::function<bool(const std::filesystem::path& path)>;
/// The result of the control API's `list` at a control socket (docs/control-api.md).
using PortLister = std::function<nlohmann::json(const std::filesystem::path& socket)>;

/// The PTY paths `dxlemu exec` protects, in order, without repeats: every --port; the `pty` and
/// `link` of each port `list` reports at each --control socket; with neither, those of every
/// daemon whose control socket `find` reports in `dir` (where `dxlemu run` puts dxlemu-PID.sock).
/// Throws std::invalid_argument naming the problem when a --port is not a character device, a
/// path is relative or holds a ':' (DXLEMU_PTYS separates paths with it), a `list` result has
/// no ports, or no daemon is found.
std::vector<std::string> exec_pty_paths(const ExecArguments& arguments,
                                        const std::filesystem::path& dir,
                                        const LiveSocketFinder& find, const PortLister& list,
                                        const CharacterDeviceTest& is_character_device);

/// Where `dxlemu exec` takes the preload library from, the first of: `override_path`
/// ($DXLEMU_PRELOAD) when set and not empty, which must exist; kPreloadLibraryName in `exe_dir`
/// (a build tree); `exe_dir`/`bindir_to_preloaddir` (an installed tree, under any prefix).
/// Throws std::runtime_error naming every place looked at when there is none, and for a path
/// LD_PRELOAD cannot carry (with a ':' or a space).
std::filesystem::path preload_library(
    const char* override_path, const std::filesystem::path& exe_dir,
    const std::filesystem::path& bindir_to_preloaddir,
    const std::function<bool(const std::filesystem::path&)>& exists);

/// `existing` (a colon-separated list, or nullptr when unset) with `added` appended, each
/// element once: LD_PRELOAD and DXLEMU_PTYS of the command.
std::string append_to_list(const char* existing, const std::vector<std::string>& added);

/// For `dxlemu exec ... -- COMMAND...` (CLI11 would hand what follows -- to the top-level
/// command): stores COMMAND in `command` and returns the number of arguments to parse, those
/// before --. Any other command line is returned whole (`argc`).
int exec_split(int argc, const char* const* argv, std::vector<std::string>& command);

}  // namespace dxlemu::app
