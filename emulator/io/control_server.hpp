#pragma once

#include <boost/asio/io_context.hpp>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace dxlemu::io {

/// One client connection of the control socket. Owned by the ControlServer; a reference stays
/// valid until the server's on_close callback has run for it.
class ControlSession {
 public:
  virtual ~ControlSession() = default;
  /// Queues `line` (a newline is appended) to this client; safe to call from a handler or later
  /// (events), dropped silently if the client has gone. A client that stops reading while more
  /// than ControlServer::kMaxQueuedBytes wait for it is disconnected.
  virtual void send(std::string line) = 0;
  /// A number unique to this connection (among all connections of one server, starting at 1).
  virtual std::uint64_t id() const = 0;
};

/// Serves newline-delimited requests on a Unix-domain stream socket created with mode 0600.
/// Many clients at once; each line is handed to the handler and its return value (a reply line,
/// without newline) is written back in order. A line longer than max_line bytes gets the
/// Replies::oversize reply and is discarded up to its newline; the connection stays up. Clients
/// that disconnect (also mid-line) are forgotten without affecting others.
///
/// Lines end with "\n"; a "\r" before it is dropped (and not counted against max_line). Empty
/// lines get no reply, and neither does a line whose handler returns an empty string.
/// Everything runs on the io_context's thread; no callback is ever called from another one.
class ControlServer {
 public:
  /// Answers one request line (without its line end). Documented not to throw; if it does
  /// anyway, the client gets the Replies::internal_error reply.
  using Handler = std::function<std::string(std::string_view line, ControlSession& session)>;
  /// The replies the server makes itself, for lines that no handler answered (the server knows
  /// nothing of what a reply looks like).
  struct Replies {
    /// To a line longer than `limit` bytes, which is discarded.
    std::function<std::string(std::size_t limit)> oversize;
    /// To a line whose handler threw `what`.
    std::function<std::string(std::string_view what)> internal_error;
  };

  /// The default limit on the length of one request line, in bytes.
  static constexpr std::size_t kDefaultMaxLine = std::size_t{64} * 1024;
  /// Bytes queued to one client above which the server stops reading its requests until the
  /// client has read enough of the replies (back-pressure on a client that only writes).
  static constexpr std::size_t kPauseReadingAbove = std::size_t{1024} * 1024;
  /// Bytes queued to one client (not counting the line being queued) above which the client is
  /// taken as not reading at all and disconnected, rather than letting events pile up forever.
  static constexpr std::size_t kMaxQueuedBytes = std::size_t{16} * 1024 * 1024;

  /// Binds `path` (an existing socket file there is replaced only if nothing listens on it;
  /// any other existing file, or a live socket, is an error: throws std::system_error naming
  /// the path), listens, and starts accepting on `io`.
  ControlServer(boost::asio::io_context& io, std::filesystem::path path, Handler handler,
                Replies replies, std::size_t max_line = kDefaultMaxLine);
  /// Stops accepting, closes every session (calling on_close for each), and unlinks the path if
  /// it is still the socket this server created.
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  /// The socket's path, as given.
  const std::filesystem::path& path() const;
  /// Called after `handler` for each session that closes (to drop event subscriptions). Never
  /// called from inside `handler` or ControlSession::send: a close is reported from its own
  /// io_context handler, or from the destructor for the sessions still open then.
  void on_close(std::function<void(ControlSession&)> callback);
  /// Sessions open now.
  std::size_t sessions() const;

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace dxlemu::io
