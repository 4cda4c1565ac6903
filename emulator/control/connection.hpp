#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace dxlemu::control {

/// A client connection as the control API sees it: which one sent a request, and how to reach it
/// later with events (trace.subscribe). The transport (io/'s control socket, a test) makes one per
/// request; a target keeps a copy only until the transport reports the connection closed, so
/// `send` never outlives what it writes to.
struct Connection {
  /// Unique among the open connections, never 0.
  std::uint64_t id = 0;
  /// Queues one event line (JSON, without its newline) for the client.
  std::function<void(std::string line)> send;
  /// The client may only look: every command that changes anything is refused
  /// (`dxlemu run --web-read-only`).
  bool read_only = false;
};

}  // namespace dxlemu::control
