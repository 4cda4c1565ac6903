#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dxlemu::app {

/// The request `dxlemu ctl COMMAND ARG...` sends to the control API (docs/control-api.md "From a
/// shell: dxlemu ctl"): {"id": 1, "cmd": COMMAND, ...}. Each ARG is either `key=value`, where the
/// value is taken as JSON when it parses as JSON (`servo=3`, `blocked=true`,
/// `rule={"action":"drop_reply"}`) and as a string otherwise (`item=goal_position`), or one JSON
/// object whose members are added. Throws std::invalid_argument naming the ARG when it is neither,
/// its key is empty, a key comes twice, or a key is `id` or `cmd` (set by ctl itself).
nlohmann::ordered_json ctl_request(std::string_view command, const std::vector<std::string>& args);

/// What `dxlemu ctl` does with the daemon's reply line: the text for stdout and stderr and the exit
/// status.
struct CtlOutcome {
  int exit_code = 0;
  std::string out;  ///< the result as indented JSON and a newline, when the request succeeded
  std::string err;  ///< "dxlemu ctl: <error>" and a newline, when it did not
};

/// Turns a reply line ({"id":..,"ok":true,"result":..} or {"ok":false,"error":".."}) into what
/// ctl prints: exit 0 and the result on success; exit 1 and the error for a refused request or a
/// reply that is not such an object.
CtlOutcome ctl_outcome(std::string_view reply_line);

/// Lists the control sockets in a directory that accept a connection now (the io layer's
/// live_control_sockets).
using LiveSocketFinder =
    std::function<std::vector<std::filesystem::path>(const std::filesystem::path& dir)>;

/// The socket `dxlemu ctl` talks to: `option` (--control) when given; else `env`
/// ($DXLEMU_CONTROL) when set and not empty; else the only live socket `find` reports in `dir`
/// (where `dxlemu run` puts dxlemu-PID.sock by default). Throws std::invalid_argument, listing
/// what was found and saying to pass --control, when there is none or more than one.
std::filesystem::path ctl_control_socket(const std::optional<std::filesystem::path>& option,
                                         const char* env, const std::filesystem::path& dir,
                                         const LiveSocketFinder& find);

}  // namespace dxlemu::app
