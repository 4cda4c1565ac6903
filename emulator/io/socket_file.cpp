#include "io/socket_file.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace dxlemu::io {
namespace {

[[noreturn]] void fail(int error, const std::string& what) {
  throw std::system_error(error, std::generic_category(), what);
}

sockaddr_un address_of(const std::filesystem::path& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(static_cast<char*>(address.sun_path), path.c_str(), path.native().size());
  return address;
}

// A socket file nobody listens on is left behind by a server that crashed: replace it. Anything
// else at `path` belongs to someone and is refused. The probe is a non-blocking connect, so a
// live server with a full backlog (EAGAIN) counts as live rather than blocking us.
void remove_stale_socket(const std::filesystem::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) {
      return;
    }
    fail(errno, "inspecting " + describe_socket(path));
  }
  if (!S_ISSOCK(st.st_mode)) {
    fail(EEXIST, describe_socket(path) + ": the path exists and is not a socket");
  }
  const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (probe < 0) {
    fail(errno, "probing " + describe_socket(path));
  }
  const sockaddr_un address = address_of(path);
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
  const int connected =
      ::connect(probe, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  const int error = errno;
  ::close(probe);
  if (connected == 0 || error == EAGAIN) {
    fail(EADDRINUSE, describe_socket(path) + ": another server is listening on it");
  }
  if (error != ECONNREFUSED) {
    fail(error, "probing " + describe_socket(path));
  }
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
    fail(errno, "removing the stale " + describe_socket(path));
  }
}

}  // namespace

std::string describe_socket(const std::filesystem::path& path) {
  return "control socket " + path.string();
}

void prepare_socket_path(const std::filesystem::path& path) {
  if (path.empty() || path.native().size() >= sizeof(sockaddr_un::sun_path)) {
    fail(ENAMETOOLONG, describe_socket(path) + ": a Unix socket path must have 1 to " +
                           std::to_string(sizeof(sockaddr_un::sun_path) - 1) + " bytes");
  }
  remove_stale_socket(path);
}

std::optional<FileIdentity> restrict_socket_file(const std::filesystem::path& path) {
  struct stat st {};
  if (::chmod(path.c_str(), kSocketMode) != 0 || ::lstat(path.c_str(), &st) != 0) {
    return std::nullopt;
  }
  return FileIdentity{st.st_dev, st.st_ino};
}

void remove_if_same(const std::filesystem::path& path, const FileIdentity& identity) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && st.st_dev == identity.device &&
      st.st_ino == identity.inode) {
    ::unlink(path.c_str());
  }
}

}  // namespace dxlemu::io
