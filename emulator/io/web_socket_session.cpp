#include "io/web_socket_session.hpp"

#include <algorithm>
#include <boost/asio/buffer.hpp>
#include <boost/beast/core/role.hpp>
#include <boost/beast/http/field.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <boost/beast/websocket/stream_base.hpp>
#include <utility>

namespace dxlemu::io::web {

namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;
using Clock = std::chrono::steady_clock;

namespace session_detail {

std::string dropped_line(std::uint64_t count, std::uint64_t total) {
  return R"({"event":"dropped","count":)" + std::to_string(count) + R"(,"total":)" +
         std::to_string(total) + "}";
}

}  // namespace session_detail

WebSocketSession::WebSocketSession(std::weak_ptr<WebSocketOwner> owner, beast::tcp_stream stream,
                                   std::uint64_t id,
                                   std::shared_ptr<const WebServerOptions> options)
    : owner_(std::move(owner)),
      ws_(std::move(stream)),
      id_(id),
      options_(std::move(options)),
      event_timer_(ws_.get_executor()),
      write_timer_(ws_.get_executor()) {}

void WebSocketSession::start(const beast::http::request<beast::http::empty_body>& upgrade) {
  // The WebSocket stream keeps its own time limits (handshake, close, idle with pings); the TCP
  // stream's would also cut the read that waits for the next request.
  beast::get_lowest_layer(ws_).expires_never();
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
    response.set(beast::http::field::server, "dxlemu");
  }));
  ws_.read_message_max(options_->max_message);
  ws_.auto_fragment(false);  // one frame per message: the client gets our batches whole
  ws_.text(true);
  ws_.async_accept(upgrade, [self = shared_from_this()](const beast::error_code& ec) {
    if (ec) {
      self->close_self();
      return;
    }
    self->read_more();
  });
}

bool WebSocketSession::shut() {
  if (closed_) {
    return false;
  }
  closed_ = true;
  event_timer_.cancel();
  write_timer_.cancel();
  beast::get_lowest_layer(ws_).close();
  return true;
}

void WebSocketSession::close_self() {
  if (const auto owner = owner_.lock()) {
    owner->close(*this);
  } else {
    shut();
  }
}

void WebSocketSession::read_more() {
  if (closed_ || closing_ || reading_ || reply_bytes_ > options_->pause_reading_above) {
    return;
  }
  reading_ = true;
  ws_.async_read(read_buffer_,
                 [self = shared_from_this()](const beast::error_code& ec, std::size_t) {
                   self->reading_ = false;
                   if (self->closed_ || self->closing_) {
                     return;
                   }
                   // Also a message over max_message: Beast has closed with 1009 already.
                   if (ec) {
                     self->close_self();
                     return;
                   }
                   self->on_message();
                 });
}

void WebSocketSession::on_message() {
  if (!ws_.got_text()) {
    refuse_binary();
    return;
  }
  const auto owner = owner_.lock();
  if (!owner) {
    shut();
    return;
  }
  const auto data = read_buffer_.cdata();
  std::string_view text(static_cast<const char*>(data.data()), data.size());
  while (!text.empty() && !closed_) {
    const std::size_t newline = text.find('\n');
    std::string_view line = text.substr(0, newline);
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    if (!line.empty() && line.back() == '\r') {
      line.remove_suffix(1);
    }
    if (line.empty()) {
      continue;
    }
    std::string reply = owner->answer(line, *this);
    if (!reply.empty()) {
      reply_bytes_ += reply.size();
      replies_.push_back({next_order_++, std::move(reply)});
    }
  }
  read_buffer_.consume(read_buffer_.size());
  flush();  // replies do not wait
  read_more();
}

void WebSocketSession::refuse_binary() {
  closing_ = true;
  ws_.async_close(
      websocket::close_reason(websocket::close_code::unknown_data,
                              "binary messages are not accepted: send request lines as text"),
      [self = shared_from_this()](const beast::error_code&) { self->close_self(); });
}

void WebSocketSession::send_event(std::string line) {
  if (closed_ || closing_ || line.empty()) {
    return;
  }
  event_bytes_ += line.size();
  events_.push_back({next_order_++, std::move(line)});
  const bool full = events_.size() >= options_->max_queued_events ||
                    event_bytes_ >= options_->max_queued_event_bytes;
  if (full && !write_busy_) {
    flush();  // the client keeps up: a burst goes out at once rather than being dropped
    return;
  }
  // Behind: the oldest go.
  std::uint64_t dropped = 0;
  while (!events_.empty() && (events_.size() > options_->max_queued_events ||
                              event_bytes_ > options_->max_queued_event_bytes)) {
    event_bytes_ -= events_.front().text.size();
    events_.pop_front();
    ++dropped;
  }
  if (dropped > 0) {
    dropped_unreported_ += dropped;
    dropped_total_ += dropped;
    if (const auto owner = owner_.lock()) {
      owner->count_dropped(dropped);
    }
  }
  schedule_events();
}

void WebSocketSession::schedule_events() {
  if (closed_ || closing_ || write_busy_ || event_timer_armed_ ||
      (events_.empty() && dropped_unreported_ == 0)) {
    return;
  }
  event_timer_armed_ = true;
  // Even when due now, the timer runs after the current handler: what it sends goes together.
  event_timer_.expires_at(std::max(Clock::now(), last_events_ + options_->event_interval));
  event_timer_.async_wait([weak = weak_from_this()](const beast::error_code& ec) {
    const auto self = weak.lock();
    if (!self) {
      return;
    }
    self->event_timer_armed_ = false;
    if (ec || self->closed_) {
      return;
    }
    // Events went out with a reply meanwhile: wait the interval from then.
    if (Clock::now() < self->last_events_ + self->options_->event_interval) {
      self->schedule_events();
      return;
    }
    self->flush();
  });
}

void WebSocketSession::flush() {
  if (closed_ || closing_ || write_busy_ ||
      (replies_.empty() && events_.empty() && dropped_unreported_ == 0)) {
    return;
  }
  writing_.clear();  // keeps its capacity: no allocation per message once it has grown
  const auto append = [this](std::string_view line) {
    if (!writing_.empty()) {
      writing_ += '\n';
    }
    writing_ += line;
  };
  // The notice goes first: the lost events were older than any still queued.
  if (dropped_unreported_ > 0) {
    append(session_detail::dropped_line(dropped_unreported_, dropped_total_));
    dropped_unreported_ = 0;
  }
  const bool any_events = !events_.empty();
  writing_reply_bytes_ = 0;
  while (!replies_.empty() || !events_.empty()) {
    const bool reply_next =
        !replies_.empty() && (events_.empty() || replies_.front().order < events_.front().order);
    std::deque<Queued>& queue = reply_next ? replies_ : events_;
    append(queue.front().text);
    if (reply_next) {
      writing_reply_bytes_ += queue.front().text.size();
    }
    queue.pop_front();
  }
  event_bytes_ = 0;
  if (any_events) {
    last_events_ = Clock::now();
  }
  write_busy_ = true;
  const std::uint64_t write = ++writes_;
  write_timer_.expires_after(options_->write_timeout);
  write_timer_.async_wait([weak = weak_from_this(), write](const beast::error_code& ec) {
    const auto self = weak.lock();
    if (!ec && self && self->write_busy_ && self->writes_ == write) {
      self->close_self();  // the client reads nothing: let it go
    }
  });
  ws_.async_write(boost::asio::buffer(writing_),
                  [self = shared_from_this()](const beast::error_code& ec, std::size_t) {
                    self->on_written(ec);
                  });
}

void WebSocketSession::on_written(const beast::error_code& ec) {
  write_busy_ = false;
  write_timer_.cancel();
  reply_bytes_ -= writing_reply_bytes_;
  writing_reply_bytes_ = 0;
  if (closed_ || closing_) {
    return;
  }
  if (ec) {
    close_self();
    return;
  }
  if (!replies_.empty()) {
    flush();
  } else {
    schedule_events();
  }
  read_more();  // in case reading paused for back-pressure
}

}  // namespace dxlemu::io::web
