#include "io/pty_link.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstdlib>
#include <system_error>

#include "io/errno_error.hpp"
#include "io/read_chunk.hpp"
#include "io/tty_baud.hpp"

namespace dxlemu::io {
namespace {

// Raw mode: no echo, no line discipline, no newline translation; the client may change any of
// it, which the emulator accepts.
void make_raw(int fd) {
  termios t{};
  if (tcgetattr(fd, &t) != 0) {
    throw_errno("tcgetattr on the PTY");
  }
  cfmakeraw(&t);
  cfsetispeed(&t, B57600);  // the factory rate of most models, until the client sets its own
  cfsetospeed(&t, B57600);
  if (tcsetattr(fd, TCSANOW, &t) != 0) {
    throw_errno("tcsetattr on the PTY");
  }
}

int open_master() {
  const int fd = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0 || grantpt(fd) != 0 || unlockpt(fd) != 0) {
    throw_errno("opening a pseudo-terminal");
  }
  return fd;
}

}  // namespace

PtyLink::PtyLink(boost::asio::io_context& io, std::optional<std::filesystem::path> link)
    : master_(io, open_master()), link_(std::move(link)), read_buffer_(kReadChunk) {
  const char* name = ptsname(master_.native_handle());
  if (name == nullptr) {
    throw_errno("ptsname");
  }
  slave_path_ = name;
  slave_fd_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_fd_ < 0) {
    throw_errno("opening " + slave_path_);
  }
  make_raw(slave_fd_);
  if (link_) {
    // Atomic: a temporary symlink renamed over the target, so the path never dangles half-made.
    const std::filesystem::path temp = link_->string() + ".dxlemu-tmp";
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    std::filesystem::create_symlink(slave_path_, temp);
    std::filesystem::rename(temp, *link_);
  }
}

PtyLink::~PtyLink() {
  if (link_) {
    std::error_code ignored;
    // Only our own symlink: if someone replaced it meanwhile, leave theirs alone.
    if (std::filesystem::is_symlink(*link_, ignored) &&
        std::filesystem::read_symlink(*link_, ignored) == slave_path_) {
      std::filesystem::remove(*link_, ignored);
    }
  }
  if (slave_fd_ >= 0) {
    ::close(slave_fd_);
  }
}

void PtyLink::start(OnBytes on_bytes) {
  on_bytes_ = std::move(on_bytes);
  read_more();
}

void PtyLink::read_more() {
  // Asio tries a read first, which right after a round trip finds nothing (EAGAIN). Waiting for
  // readiness instead (async_wait, then one read) was measured and costs as much: Asio then
  // re-registers the descriptor with epoll_ctl on every wait (docs/benchmarks.md "Hot spots
  // removed, before and after").
  master_.async_read_some(boost::asio::buffer(read_buffer_),
                          [this](const boost::system::error_code& ec, std::size_t n) {
                            if (ec) {
                              return;  // cancelled at shutdown
                            }
                            on_bytes_(std::span(read_buffer_.data(), n), tty_baud(slave_fd_));
                            read_more();
                          });
}

bool PtyLink::deliver(std::span<const std::uint8_t> bytes, sim::SimTime /*at*/,
                      std::uint32_t /*bps*/) {
  if (write_queue_.empty()) {
    // The usual case: the PTY has room, and the reply goes out now without a queue entry.
    const std::size_t sent = write_now(bytes);
    if (sent == bytes.size()) {
      return true;
    }
    bytes = bytes.subspan(sent);  // a packet begun is finished: never a torn reply
  } else if (queued_bytes_ + bytes.size() > kMaxQueuedBytes) {
    return false;  // nobody reads: dropped
  }
  queued_bytes_ += bytes.size();
  write_queue_.emplace_back(bytes.begin(), bytes.end());
  if (write_queue_.size() == 1) {
    write_next();
  }
  return true;
}

std::size_t PtyLink::write_now(std::span<const std::uint8_t> bytes) {
  for (;;) {
    const ssize_t n = ::write(master_.native_handle(), bytes.data(), bytes.size());
    if (n >= 0) {
      return static_cast<std::size_t>(n);
    }
    if (errno != EINTR) {
      return 0;  // EAGAIN: the PTY is full, the queue waits for room
    }
  }
}

void PtyLink::write_next() {
  boost::asio::async_write(master_, boost::asio::buffer(write_queue_.front()),
                           [this](const boost::system::error_code& ec, std::size_t) {
                             if (ec) {
                               write_queue_.clear();
                               queued_bytes_ = 0;
                               return;
                             }
                             queued_bytes_ -= write_queue_.front().size();
                             write_queue_.pop_front();
                             if (!write_queue_.empty()) {
                               write_next();
                             }
                           });
}

}  // namespace dxlemu::io
