#include "io/socket_file.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "io_rig.hpp"

namespace {

using dxlemu::io::prepare_socket_path;
using dxlemu::io::remove_if_same;
using dxlemu::io::restrict_socket_file;
using dxlemu::test::IoTempDir;
namespace fs = std::filesystem;

// A socket bound at `path`, listening or not; closed with the object (its file stays).
struct BoundSocket {
  BoundSocket(const fs::path& path, bool listening)
      : fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    REQUIRE(fd >= 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(static_cast<char*>(address.sun_path), path.c_str(), sizeof address.sun_path - 1);
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
    REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
    if (listening) {
      REQUIRE(::listen(fd, 1) == 0);
    }
  }
  ~BoundSocket() { ::close(fd); }
  BoundSocket(const BoundSocket&) = delete;
  BoundSocket& operator=(const BoundSocket&) = delete;
  int fd;
};

int error_of(const fs::path& path) {
  try {
    prepare_socket_path(path);
  } catch (const std::system_error& e) {
    return e.code().value();
  }
  return 0;
}

}  // namespace

TEST_CASE("A socket path is ready when free or left by a crashed server", "[io][socket_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "ctl.sock";
  CHECK(error_of(path) == 0);
  { BoundSocket stale(path, false); }
  REQUIRE(fs::exists(fs::symlink_status(path)));
  CHECK(error_of(path) == 0);
  CHECK_FALSE(fs::exists(fs::symlink_status(path)));
}

TEST_CASE("A socket path is refused when taken, not a socket, empty or too long",
          "[io][socket_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "ctl.sock";
  {
    BoundSocket live(path, true);
    CHECK(error_of(path) == EADDRINUSE);
    CHECK(fs::exists(fs::symlink_status(path)));
  }
  fs::remove(path);
  std::ofstream(path) << "not a socket";
  CHECK(error_of(path) == EEXIST);
  CHECK_THROWS_WITH(prepare_socket_path(path), Catch::Contains(path.string()));
  CHECK(fs::is_regular_file(path));
  CHECK(error_of("") == ENAMETOOLONG);
  CHECK(error_of(dir.path() / std::string(sizeof(sockaddr_un::sun_path), 'x')) == ENAMETOOLONG);
}

TEST_CASE("A socket file is restricted to its owner and removed only while it is the same",
          "[io][socket_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "ctl.sock";
  {
    BoundSocket socket(path, true);
    const auto ours = restrict_socket_file(path);
    REQUIRE(ours);
    CHECK((fs::status(path).permissions() & fs::perms::all) ==
          (fs::perms::owner_read | fs::perms::owner_write));
    // Replaced by another file while the socket is open (its inode still taken): left alone.
    fs::remove(path);
    std::ofstream(path) << "theirs";
    remove_if_same(path, *ours);
    CHECK(fs::is_regular_file(path));
    fs::remove(path);
  }
  {
    BoundSocket socket(path, true);
    const auto ours = restrict_socket_file(path);
    REQUIRE(ours);
    remove_if_same(path, *ours);
    CHECK_FALSE(fs::exists(fs::symlink_status(path)));
  }
  CHECK_FALSE(restrict_socket_file(path));  // gone: nothing to restrict
}
