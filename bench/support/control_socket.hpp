#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "support/serial_port.hpp"

namespace dxlemu::bench {

/// A client connection to dxlemu's control socket (docs/control-api.md): newline-delimited JSON
/// requests and replies, plus the event lines a `trace.subscribe` asks for. Blocking, one
/// request at a time; for benches that load the control API, so it parses nothing itself.
class ControlConnection {
 public:
  /// Connects to the Unix socket at `path`. Throws std::system_error naming the path.
  explicit ControlConnection(const std::string& path);
  /// Closes the connection.
  ~ControlConnection();
  ControlConnection(const ControlConnection&) = delete;
  ControlConnection& operator=(const ControlConnection&) = delete;

  /// Sends `line` (one JSON request, without its newline) and returns the reply line (without
  /// its newline). Event lines that arrive before the reply are counted (events()) and skipped.
  /// Throws when the daemon closes the connection or no reply comes before `give_up`.
  std::string call(std::string_view line, Clock::time_point give_up);

  /// Waits until something arrives or `give_up` passes, reads what there is and discards it,
  /// and returns how many lines that completed (0 on timeout): what a trace subscriber that only
  /// counts its events does. Throws when the daemon has closed the connection.
  std::size_t discard_lines(Clock::time_point give_up);

  /// How many event lines call() has skipped so far.
  std::size_t events() const { return events_; }

 private:
  enum class Received { Data, Timeout, Closed };
  // Reads once (waiting until `give_up`) and appends what came to buffer_.
  Received receive(Clock::time_point give_up);

  std::string path_;
  int fd_ = -1;
  std::string buffer_;       // bytes received and not yet handed out
  std::vector<char> chunk_;  // what one recv() fills
  std::size_t events_ = 0;
};

}  // namespace dxlemu::bench
