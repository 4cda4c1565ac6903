#pragma once

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>

#include "io/web_server.hpp"

// One WebSocket client of the web server (io/web_server.cpp): the API's request lines in, its
// replies and events out. Internal to io/.
namespace dxlemu::io::web {

class WebSocketSession;

/// What a session needs of its server.
class WebSocketOwner {
 public:
  /// The reply to one request line (the handler's, or the internal error reply).
  virtual std::string answer(std::string_view line, WebSession& session) = 0;
  /// The session has failed or finished: forget it and report its close.
  virtual void close(WebSocketSession& session) = 0;
  /// `count` more events were dropped (for WebServer::dropped_events).
  virtual void count_dropped(std::uint64_t count) = 0;

 protected:
  WebSocketOwner() = default;
  ~WebSocketOwner() = default;
  WebSocketOwner(const WebSocketOwner&) = default;
  WebSocketOwner& operator=(const WebSocketOwner&) = default;
};

/// Owned by its server's table of sessions while open, and by its own pending I/O handlers; it
/// holds only a weak reference to the server, so handlers that complete after the server is
/// gone do nothing.
class WebSocketSession final : public WebSession,
                               public std::enable_shared_from_this<WebSocketSession> {
 public:
  WebSocketSession(std::weak_ptr<WebSocketOwner> owner, boost::beast::tcp_stream stream,
                   std::uint64_t id, std::shared_ptr<const WebServerOptions> options);

  /// Completes the handshake of `upgrade` (already checked) and starts reading.
  void start(const boost::beast::http::request<boost::beast::http::empty_body>& upgrade);
  void send_event(std::string line) override;
  std::uint64_t id() const override { return id_; }
  std::uint64_t dropped_events() const override { return dropped_total_; }
  /// Closes the socket (pending operations complete as aborted) and stops the timers; false if
  /// it was closed already.
  bool shut();

 private:
  /// A line waiting to be written; `order` keeps replies and events in the order they came.
  struct Queued {
    std::uint64_t order;
    std::string text;
  };

  void read_more();
  void on_message();
  /// Closes with 1003: only text messages carry requests.
  void refuse_binary();
  /// Writes whatever is queued (replies, events, the dropped notice) as one message, unless a
  /// write is in progress (its completion comes back here).
  void flush();
  /// Arranges for the queued events to be written event_interval after the last ones.
  void schedule_events();
  void on_written(const boost::system::error_code& ec);
  void close_self();

  std::weak_ptr<WebSocketOwner> owner_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  std::uint64_t id_;
  std::shared_ptr<const WebServerOptions> options_;  // shared with the server
  boost::beast::flat_buffer read_buffer_;
  boost::asio::steady_timer event_timer_;
  boost::asio::steady_timer write_timer_;

  std::uint64_t next_order_ = 0;
  std::deque<Queued> replies_;
  std::deque<Queued> events_;
  std::size_t event_bytes_ = 0;
  std::size_t reply_bytes_ = 0;  // queued or being written
  std::uint64_t dropped_unreported_ = 0;
  std::uint64_t dropped_total_ = 0;

  std::string writing_;  // the message being written
  std::size_t writing_reply_bytes_ = 0;
  std::uint64_t writes_ = 0;  // writes started, to tell a stale write timer from the current one
  bool write_busy_ = false;
  bool reading_ = false;
  bool event_timer_armed_ = false;
  bool closing_ = false;  // a close handshake of ours is under way: no more reads or writes
  bool closed_ = false;
  std::chrono::steady_clock::time_point last_events_{};
};

}  // namespace dxlemu::io::web
