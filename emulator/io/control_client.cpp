#include "io/control_client.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "io/read_chunk.hpp"

namespace dxlemu::io {
namespace {

constexpr std::string_view kSocketPrefix = "dxlemu-";
constexpr std::string_view kSocketSuffix = ".sock";

// Opens a stream socket connected to `path`; returns -1 with errno set on failure.
int connect_to(const std::filesystem::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string text = path.string();
  if (text.size() >= sizeof(address.sun_path)) {
    errno = ENAMETOOLONG;
    return -1;
  }
  std::memcpy(address.sun_path, text.c_str(), text.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return -1;
  }
  // A Unix socket's connect() does not wait for the listener: it succeeds or fails at once.
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

}  // namespace

ControlClient::ControlClient(const std::filesystem::path& path) : path_(path) {
  fd_ = connect_to(path);
  if (fd_ < 0) {
    const int error = errno;
    std::string reason = std::strerror(error);
    if (error == ECONNREFUSED) {
      reason += " (a stale socket: the daemon is gone)";
    } else if (error == ENAMETOOLONG) {
      reason = "path too long for a Unix socket";
    }
    throw ControlConnectError("cannot connect to the control socket " + path.string() + ": " +
                              reason);
  }
}

ControlClient::~ControlClient() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

std::string ControlClient::call(std::string_view line, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::string out(line);
  out += '\n';
  for (std::size_t sent = 0; sent < out.size();) {
    // MSG_NOSIGNAL: a daemon that went away is an error here, not a SIGPIPE.
    const ssize_t n = ::send(fd_, out.data() + sent, out.size() - sent, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      throw std::system_error(errno, std::generic_category(),
                              "sending to the control socket " + path_.string());
    }
    sent += static_cast<std::size_t>(n);
  }
  std::array<char, kReadChunk> chunk{};
  while (buffer_.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd p{fd_, POLLIN, 0};
    const int ready = left.count() > 0 ? ::poll(&p, 1, static_cast<int>(left.count())) : 0;
    if (ready == 0) {
      throw std::runtime_error("no reply from the control socket " + path_.string() + " within " +
                               std::to_string(timeout.count()) + " ms");
    }
    if (ready < 0) {
      if (errno == EINTR) {
        continue;
      }
      throw std::system_error(errno, std::generic_category(), "waiting for the control socket");
    }
    const ssize_t n = ::recv(fd_, chunk.data(), chunk.size(), 0);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      throw std::system_error(errno, std::generic_category(),
                              "reading the control socket " + path_.string());
    }
    if (n == 0) {
      throw std::runtime_error("the daemon closed the control socket " + path_.string() +
                               " before replying");
    }
    buffer_.append(chunk.data(), static_cast<std::size_t>(n));
  }
  const auto end = buffer_.find('\n');
  std::string reply = buffer_.substr(0, end);
  buffer_.erase(0, end + 1);
  if (!reply.empty() && reply.back() == '\r') {
    reply.pop_back();
  }
  return reply;
}

std::vector<std::filesystem::path> live_control_sockets(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> live;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= kSocketPrefix.size() + kSocketSuffix.size() ||
        !name.starts_with(kSocketPrefix) || !name.ends_with(kSocketSuffix) ||
        !entry.is_socket(ec)) {
      continue;
    }
    const int fd = connect_to(entry.path());
    if (fd >= 0) {
      ::close(fd);
      live.push_back(entry.path());
    }
  }
  std::sort(live.begin(), live.end());
  return live;
}

}  // namespace dxlemu::io
