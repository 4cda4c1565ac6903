#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace dxlemu::io {

/// What a WebServer is told at its start. The defaults are the ones of docs/web.md.
struct WebServerOptions {
  /// The numeric address to listen on ("127.0.0.1", "::1", "0.0.0.0"; "localhost" is taken as
  /// 127.0.0.1, brackets around IPv6 are allowed). Other than loopback is allowed: warning
  /// about it is the caller's job.
  std::string address = "127.0.0.1";
  /// The TCP port; 0 takes any free one (tests), WebServer::port() tells which.
  std::uint16_t port = 0;
  /// The secret every request must carry (query `token=` or the per-port cookie). Not empty.
  std::string token;
  /// The page: index.html at "/", its other files by name.
  std::filesystem::path web_root;
  /// Served at /lib/, its three/ and chart.js/ directories only.
  std::filesystem::path library_root = "/usr/share/javascript";
  /// The largest WebSocket message accepted from a client; larger ones close it with 1009.
  std::size_t max_message = std::size_t{64} * 1024;
  /// Events to a client are gathered and written at most this often.
  std::chrono::milliseconds event_interval{40};
  /// Events waiting for one client at most (lines, bytes); beyond, its oldest are dropped.
  std::size_t max_queued_events = 4096;
  std::size_t max_queued_event_bytes = std::size_t{4} << 20;
  /// Replies waiting for one client above which its requests are read no more until it has
  /// read enough of them (replies are never dropped).
  std::size_t pause_reading_above = std::size_t{1} << 20;
  /// Open connections (HTTP and WebSocket) at most; more are answered 503 and closed.
  std::size_t max_connections = 64;
  /// How long one HTTP request (or response) may take on the wire; an idle keep-alive
  /// connection is closed after it too.
  std::chrono::milliseconds request_timeout{30000};
  /// How long one WebSocket write may stay unfinished before the client is closed.
  std::chrono::milliseconds write_timeout{30000};
  /// The id of the first WebSocket session (the next ones count up): lets the caller keep the
  /// ids apart from another server's (the control socket's start at 1).
  std::uint64_t first_session_id = 1;
};

/// One WebSocket client of a WebServer. Owned by the server; a reference stays valid until the
/// server's on_close callback has run for it.
class WebSession {
 public:
  virtual ~WebSession() = default;
  /// Queues an event line (no newline) to this client. Events are gathered and written every
  /// WebServerOptions::event_interval; a client that does not keep up loses its oldest ones
  /// (it is told how many in a `{"event":"dropped",...}` line). Safe to call from a handler or
  /// later; ignored once the client has gone, and when empty.
  virtual void send_event(std::string line) = 0;
  /// A number unique to this session among the server's (from first_session_id up).
  virtual std::uint64_t id() const = 0;
  /// Events this client has lost so far.
  virtual std::uint64_t dropped_events() const = 0;
};

/// Serves the web page over HTTP and the control API over a WebSocket at /ws, on `io`'s thread
/// (docs/web.md, "Security and limits", says what it checks and refuses).
///
/// Each text message of a WebSocket client holds one or more request lines separated by "\n";
/// each line (without a "\r" before its "\n"; empty ones skipped) goes to the handler and its
/// return value (if not empty) back to the client at once. Replies and events reach the client
/// in the order they were made, several lines to a message joined by "\n". Everything runs on
/// the io_context's thread; no callback is ever called from another one.
class WebServer {
 public:
  /// Answers one request line. Documented not to throw; if it does anyway, the client gets the
  /// Replies::internal_error reply.
  using Handler = std::function<std::string(std::string_view line, WebSession& session)>;
  /// The replies the server makes itself (it knows nothing of what a reply looks like).
  struct Replies {
    /// To a line whose handler threw `what`.
    std::function<std::string(std::string_view what)> internal_error;
  };

  /// Listens on options.address:options.port and starts accepting on `io`. Throws
  /// std::system_error naming the address and port when it cannot listen (a port in use, an
  /// address not of this machine, a malformed address), std::invalid_argument for an empty
  /// token.
  WebServer(boost::asio::io_context& io, WebServerOptions options, Handler handler,
            Replies replies);
  /// Stops accepting, closes every connection, and calls on_close for each WebSocket session
  /// still open.
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  /// The port listened on (the one chosen when options.port was 0).
  std::uint16_t port() const;
  /// The page's address with the token, "http://127.0.0.1:8080/?token=..." (IPv6 in brackets;
  /// an unspecified address, 0.0.0.0 or ::, is given as 127.0.0.1 or [::1]).
  std::string url() const;
  /// Whether the listening address is a loopback one (else the page is reachable from other
  /// machines: the caller warns).
  bool loopback() const;
  /// Called for each WebSocket session that closes (to drop its subscriptions). Never called
  /// from inside the handler or WebSession::send_event: a close is reported from an io_context
  /// handler of its own, or from the destructor for the sessions still open then.
  void on_close(std::function<void(WebSession&)> callback);
  /// WebSocket sessions open now.
  std::size_t sessions() const;
  /// Connections open now, HTTP and WebSocket.
  std::size_t connections() const;
  /// Events dropped so far over all clients, including gone ones (for stats).
  std::uint64_t dropped_events() const;

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace dxlemu::io
