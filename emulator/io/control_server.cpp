// The control socket's server: sessions, line splitting and write queues. What concerns the
// socket's file on disk (stale sockets, mode, removal) is io/socket_file.*.
#include "io/control_server.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <optional>
#include <utility>

#include "io/accept_again.hpp"
#include "io/read_chunk.hpp"
#include "io/session_table.hpp"
#include "io/socket_file.hpp"

namespace dxlemu::io {
namespace {

using boost::asio::local::stream_protocol;

// A callback documented not to throw that throws anyway gets the internal_error reply.
template <typename Fn>
std::string call_safely(const ControlServer::Replies& replies, Fn&& fn) {
  try {
    return std::forward<Fn>(fn)();
  } catch (const std::exception& e) {
    return replies.internal_error(e.what());
  } catch (...) {
    return replies.internal_error("unknown exception");
  }
}

}  // namespace

struct ControlServer::State : std::enable_shared_from_this<State> {
  class Session;

  State(boost::asio::io_context& io, std::filesystem::path path, Handler handler, Replies replies,
        std::size_t max_line);

  void accept();
  /// Closes `session` and reports it to on_close from a handler of its own (never re-entrantly
  /// from inside a handler or send()).
  void close(Session& session) { sessions.close(session); }
  /// Closes everything (the server's destructor).
  void stop();

  boost::asio::io_context& io;
  std::filesystem::path path;
  Handler handler;
  Replies replies;
  std::size_t max_line;
  stream_protocol::acceptor acceptor;
  boost::asio::steady_timer retry_timer;
  FileIdentity file;  // the socket file we created, so that the destructor unlinks only our own
  std::uint64_t next_id = 1;
  SessionTable<Session, ControlSession> sessions;
  bool stopped = false;
};

/// One connection. Owned by the State's session table while open, and by its own pending I/O
/// handlers; it holds only a weak reference to the State, so handlers that complete after the
/// server is gone do nothing.
class ControlServer::State::Session final : public ControlSession,
                                            public std::enable_shared_from_this<Session> {
 public:
  Session(std::weak_ptr<State> state, stream_protocol::socket socket, std::uint64_t id)
      : state_(std::move(state)), socket_(std::move(socket)), id_(id) {}

  void send(std::string line) override;
  std::uint64_t id() const override { return id_; }

  void start() { read_more(); }
  /// Closes the socket (pending reads and writes complete as aborted); returns false if it was
  /// closed already.
  bool shut();

 private:
  void read_more();
  void consume(std::string_view bytes, State& state);
  void answer(std::string_view line, State& state);
  /// Writes every line sent so far, in one write when it can.
  void flush();
  /// Bytes sent and not yet written.
  std::size_t queued_bytes() const { return pending_.size() + writing_.size(); }
  void close_self();

  std::weak_ptr<State> state_;
  stream_protocol::socket socket_;
  std::uint64_t id_;
  std::array<char, kReadChunk> read_buffer_{};
  std::string line_;         // the request received so far, without its line end
  bool discarding_ = false;  // inside an oversize line, until its newline
  bool reading_ = false;
  bool peer_done_ = false;  // the client shut down its sending side
  bool closed_ = false;
  // Lines are gathered and written together: a trace subscriber gets two events per round trip
  // on the bus, and one write (one wake-up of the reader) instead of two halves what its events
  // cost the daemon (docs/benchmarks.md).
  std::string pending_;  // sent, waiting for the write in progress or a posted flush
  std::string writing_;  // being written
  bool flush_posted_ = false;
};

ControlServer::State::State(boost::asio::io_context& io, std::filesystem::path path,
                            Handler handler, Replies replies, std::size_t max_line)
    : io(io),
      path(std::move(path)),
      handler(std::move(handler)),
      replies(std::move(replies)),
      max_line(max_line),
      acceptor(io),
      retry_timer(io),
      sessions(io) {
  const std::string what = describe_socket(this->path);
  prepare_socket_path(this->path);
  boost::system::error_code ec;
  acceptor.open(stream_protocol(), ec);
  throw_if_failed(ec, "creating " + what);
  // Linux creates the socket file with the socket's own mode (less the umask), so after this no
  // other user can connect even in the moment between bind and the chmod below (which makes
  // sure on systems where it does not).
  ::fchmod(acceptor.native_handle(), kSocketMode);
  acceptor.bind(stream_protocol::endpoint(this->path.string()), ec);
  throw_if_failed(ec, "binding " + what);
  const std::optional<FileIdentity> made = restrict_socket_file(this->path);
  const int error = errno;
  if (made) {
    file = *made;
    acceptor.listen(boost::asio::socket_base::max_listen_connections, ec);
  }
  if (!made || ec) {
    ::unlink(this->path.c_str());
    throw_if_failed(made ? ec : boost::system::error_code(error, boost::system::system_category()),
                    "setting up " + what);
  }
}

void ControlServer::State::accept() {
  acceptor.async_accept([weak = weak_from_this()](const boost::system::error_code& ec,
                                                  stream_protocol::socket socket) {
    const auto self = weak.lock();
    if (!self || self->stopped) {
      return;
    }
    if (ec) {
      accept_again_later(self->retry_timer, weak);
      return;
    }
    const std::uint64_t id = self->next_id++;
    auto session = std::make_shared<Session>(weak, std::move(socket), id);
    self->sessions.add(session);
    session->start();
    self->accept();
  });
}

void ControlServer::State::stop() {
  stopped = true;
  boost::system::error_code ignored;
  acceptor.close(ignored);
  retry_timer.cancel();
  // Only our own socket file: if another server replaced it meanwhile, leave theirs alone.
  remove_if_same(path, file);
  sessions.close_all();
}

bool ControlServer::State::Session::shut() {
  if (closed_) {
    return false;
  }
  closed_ = true;
  boost::system::error_code ignored;
  socket_.close(ignored);
  return true;
}

void ControlServer::State::Session::close_self() {
  if (const auto state = state_.lock()) {
    state->close(*this);
  } else {
    shut();
  }
}

void ControlServer::State::Session::send(std::string line) {
  if (closed_) {
    return;
  }
  if (queued_bytes() > kMaxQueuedBytes) {
    close_self();  // the client reads nothing; keeping its events would only exhaust memory
    return;
  }
  pending_ += line;
  pending_ += '\n';
  // Written once the handler that sent it is done, together with whatever else it sends.
  if (writing_.empty() && !flush_posted_) {
    flush_posted_ = true;
    boost::asio::post(socket_.get_executor(), [self = shared_from_this()] {
      self->flush_posted_ = false;
      self->flush();
    });
  }
}

void ControlServer::State::Session::flush() {
  if (closed_ || pending_.empty() || !writing_.empty()) {
    return;
  }
  std::swap(writing_, pending_);  // both keep their capacity: no allocation per line
  boost::asio::async_write(
      socket_, boost::asio::buffer(writing_),
      [self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
        self->writing_.clear();
        if (ec || self->closed_) {
          self->pending_.clear();
          self->close_self();
          return;
        }
        if (!self->pending_.empty()) {
          self->flush();
        } else if (self->peer_done_) {
          self->close_self();  // every reply is out and no request can come
          return;
        }
        self->read_more();  // in case reading paused for back-pressure
      });
}

void ControlServer::State::Session::read_more() {
  if (closed_ || reading_ || peer_done_ || queued_bytes() > kPauseReadingAbove) {
    return;
  }
  reading_ = true;
  socket_.async_read_some(
      boost::asio::buffer(read_buffer_),
      [self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
        self->reading_ = false;
        const auto state = self->state_.lock();
        if (!state || state->stopped || self->closed_) {
          return;
        }
        if (ec == boost::asio::error::eof) {
          // A half-close (`nc -N`, socat) still gets the replies to its complete lines; an
          // unfinished last line is dropped.
          self->peer_done_ = true;
          if (self->queued_bytes() == 0) {
            state->close(*self);
          }
          return;
        }
        if (ec) {
          state->close(*self);
          return;
        }
        self->consume(std::string_view(self->read_buffer_.data(), n), *state);
        self->read_more();
      });
}

// Lines are split here rather than with async_read_until so that a line is refused as soon as
// it exceeds the limit, without buffering it, and the rest of it up to its newline is skipped.
void ControlServer::State::Session::consume(std::string_view bytes, State& state) {
  while (!bytes.empty() && !closed_ && !state.stopped) {
    const std::size_t newline = bytes.find('\n');
    const bool complete = newline != std::string_view::npos;
    const std::string_view piece = bytes.substr(0, newline);
    bytes.remove_prefix(complete ? newline + 1 : bytes.size());
    if (discarding_) {
      discarding_ = !complete;
      continue;
    }
    // A trailing '\r' is not part of the line (and one still waiting for its '\n' may become
    // that), so it does not count against the limit.
    const std::size_t length = line_.size() + piece.size();
    const char last = !piece.empty() ? piece.back() : (!line_.empty() ? line_.back() : '\0');
    if ((last == '\r' ? length - 1 : length) > state.max_line) {
      line_.clear();
      discarding_ = !complete;
      std::string reply =
          call_safely(state.replies, [&] { return state.replies.oversize(state.max_line); });
      if (!reply.empty()) {
        send(std::move(reply));
      }
      continue;
    }
    line_.append(piece);
    if (!complete) {
      continue;
    }
    if (!line_.empty() && line_.back() == '\r') {
      line_.pop_back();
    }
    if (!line_.empty()) {
      answer(line_, state);
    }
    line_.clear();
  }
}

void ControlServer::State::Session::answer(std::string_view line, State& state) {
  std::string reply = call_safely(state.replies, [&] { return state.handler(line, *this); });
  if (!reply.empty()) {
    send(std::move(reply));
  }
}

ControlServer::ControlServer(boost::asio::io_context& io, std::filesystem::path path,
                             Handler handler, Replies replies, std::size_t max_line)
    : state_(std::make_shared<State>(io, std::move(path), std::move(handler), std::move(replies),
                                     max_line)) {
  state_->accept();
}

ControlServer::~ControlServer() {
  state_->stop();
}

const std::filesystem::path& ControlServer::path() const {
  return state_->path;
}

void ControlServer::on_close(std::function<void(ControlSession&)> callback) {
  state_->sessions.on_close(std::move(callback));
}

std::size_t ControlServer::sessions() const {
  return state_->sessions.size();
}

}  // namespace dxlemu::io
