#include "support/control_socket.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dxlemu::bench {

namespace {

// Large enough that a subscriber drains a burst of trace events in few read()s.
constexpr std::size_t kReadChunk = std::size_t{64} * 1024;
// dxlemu writes every event as {"event":...} (nlohmann's dump without spaces, event first), and
// a reply never has that key: a prefix test tells them apart without parsing.
constexpr std::string_view kEventPrefix = R"({"event")";

}  // namespace

ControlConnection::ControlConnection(const std::string& path) : path_(path), chunk_(kReadChunk) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof(address.sun_path)) {
    errno = ENAMETOOLONG;
    fail("control socket " + path);
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    fail("socket");
  }
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    const int error = errno;
    ::close(fd_);
    errno = error;
    fail("connecting to the control socket " + path);
  }
}

ControlConnection::~ControlConnection() {
  ::close(fd_);
}

std::string ControlConnection::call(std::string_view line, Clock::time_point give_up) {
  std::string out(line);
  out += '\n';
  for (std::size_t sent = 0; sent < out.size();) {
    // MSG_NOSIGNAL: a daemon that went away is an error here, not a SIGPIPE.
    const ssize_t n = ::send(fd_, out.data() + sent, out.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno != EINTR) {
      fail("sending to the control socket " + path_);
    }
    sent += n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = buffer_.find('\n', start);
    if (end == std::string::npos) {
      buffer_.erase(0, start);
      start = 0;
      const Received got = receive(give_up);
      if (got != Received::Data) {
        throw std::runtime_error(got == Received::Closed
                                     ? "the daemon closed the control socket " + path_
                                     : "no reply from the control socket " + path_);
      }
      continue;
    }
    const std::string_view text(buffer_.data() + start, end - start);
    if (text.starts_with(kEventPrefix)) {
      ++events_;
      start = end + 1;
      continue;
    }
    std::string reply(text);
    buffer_.erase(0, end + 1);
    return reply;
  }
}

std::size_t ControlConnection::discard_lines(Clock::time_point give_up) {
  const Received got = receive(give_up);
  if (got == Received::Closed) {
    throw std::runtime_error("the daemon closed the control socket " + path_);
  }
  if (got == Received::Timeout) {
    return 0;
  }
  // Only the newlines matter; what follows the last one is the start of the next line.
  const auto lines = static_cast<std::size_t>(std::count(buffer_.begin(), buffer_.end(), '\n'));
  buffer_.erase(0, buffer_.rfind('\n') + 1);
  return lines;
}

ControlConnection::Received ControlConnection::receive(Clock::time_point give_up) {
  for (;;) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(give_up - Clock::now());
    pollfd p{fd_, POLLIN, 0};
    const int ready = left.count() > 0 ? ::poll(&p, 1, static_cast<int>(left.count())) : 0;
    if (ready < 0 && errno == EINTR) {
      continue;
    }
    if (ready < 0) {
      fail("waiting for the control socket " + path_);
    }
    if (ready == 0) {
      return Received::Timeout;
    }
    const ssize_t n = ::recv(fd_, chunk_.data(), chunk_.size(), 0);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0) {
      fail("reading the control socket " + path_);
    }
    if (n == 0) {
      return Received::Closed;
    }
    buffer_.append(chunk_.data(), static_cast<std::size_t>(n));
    return Received::Data;
  }
}

}  // namespace dxlemu::bench
