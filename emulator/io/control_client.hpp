#pragma once

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dxlemu::io {

/// Nothing accepts a connection at a control socket's path (no such file, not a socket, no
/// daemon listening, no permission). The message names the path and the reason.
class ControlConnectError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A blocking client of the control API's Unix socket (docs/control-api.md), for `dxlemu ctl`:
/// one connection, one request line at a time. Plain POSIX sockets: ctl runs no io_context.
class ControlClient {
 public:
  /// Connects to the socket at `path`. Throws ControlConnectError naming the path.
  explicit ControlClient(const std::filesystem::path& path);
  /// Closes the connection.
  ~ControlClient();
  ControlClient(const ControlClient&) = delete;
  ControlClient& operator=(const ControlClient&) = delete;

  /// Sends `line` and a newline, and returns the reply line (without its newline), waiting at
  /// most `timeout` (wall clock) in all. Throws std::runtime_error when the daemon closes the
  /// connection first or the time runs out, std::system_error when the socket fails.
  std::string call(std::string_view line, std::chrono::milliseconds timeout);

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::string buffer_;  // bytes received after the last reply line
};

/// The files named dxlemu-*.sock in `dir` that accept a connection now (a daemon listens), sorted
/// by name. Stale sockets of killed daemons, other files and an unreadable `dir` are skipped.
std::vector<std::filesystem::path> live_control_sockets(const std::filesystem::path& dir);

}  // namespace dxlemu::io
