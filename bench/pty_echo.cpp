// The physical limit of throughput: a pseudo-terminal with a process behind it that answers
// without doing any work, to compare dxlemu's round trips with.
//
// It opens a PTY as dxlemu does (posix_openpt, raw, its own slave descriptor kept open so that
// clients may come and go), prints a readiness line like dxlemu's
//
//   {"event":"ready","port":"dxl0","pty":"/dev/pts/N"}
//
// so that bench::Daemon starts it like dxlemu, and then, for every 14 bytes it reads (a Protocol
// 2.0 Read of 4 bytes), writes back one canned 15-byte status: the bytes dxlemu answers to a Read
// of Present Position (132, 4 bytes) from ID 1, an XM430-W350 standing at 2048. It parses
// nothing, keeps no time and waits in a blocking read(2): the least a process can do per round
// trip. It runs until SIGTERM, whose default action ends it (there is nothing to clean up).
//
// Usage: pty_echo
#include <fcntl.h>
#include <stdlib.h>  // NOLINT(modernize-deprecated-headers): posix_openpt and friends are POSIX
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/read_position.hpp"
#include "support/serial_port.hpp"

namespace {

namespace bench = dxlemu::bench;

constexpr std::uint8_t kServoId = 1;
constexpr std::size_t kReadChunk = 4096;

int open_master() {
  const int fd = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0 || grantpt(fd) != 0 || unlockpt(fd) != 0) {
    bench::fail("opening a pseudo-terminal");
  }
  return fd;
}

// Opens the slave raw and returns it. Keeping it open means a client's close() never leaves the
// master reading EIO, as in dxlemu's PtyLink.
int open_slave(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    bench::fail("opening " + path);
  }
  termios t{};
  if (tcgetattr(fd, &t) != 0) {
    bench::fail("tcgetattr on the PTY");
  }
  cfmakeraw(&t);
  if (tcsetattr(fd, TCSANOW, &t) != 0) {
    bench::fail("tcsetattr on the PTY");
  }
  return fd;
}

void write_all(int fd, const std::vector<std::uint8_t>& bytes) {
  for (std::size_t sent = 0; sent < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + sent, bytes.size() - sent);
    if (n < 0 && errno != EINTR) {
      bench::fail("write");
    }
    sent += n > 0 ? static_cast<std::size_t>(n) : 0;
  }
}

}  // namespace

int main() {
  try {
    const std::size_t instruction_size = bench::read_position_instruction(kServoId).size();
    const std::vector<std::uint8_t> status =
        bench::read_position_status(kServoId, bench::kStartPosition);
    const int master = open_master();
    const char* name = ptsname(master);
    if (name == nullptr) {
      bench::fail("ptsname");
    }
    const std::string slave_path = name;
    // Open for the whole life of the process: see open_slave.
    [[maybe_unused]] const int slave = open_slave(slave_path);
    std::cout << nlohmann::json{{"event", "ready"}, {"port", "dxl0"}, {"pty", slave_path}}.dump()
              << std::endl;
    std::array<std::uint8_t, kReadChunk> buffer{};
    std::size_t pending = 0;  // bytes of an instruction not yet complete
    for (;;) {
      const ssize_t n = ::read(master, buffer.data(), buffer.size());
      if (n < 0 && errno != EINTR) {
        bench::fail("read");
      }
      for (pending += n > 0 ? static_cast<std::size_t>(n) : 0; pending >= instruction_size;
           pending -= instruction_size) {
        write_all(master, status);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "pty_echo: " << e.what() << "\n";
    return 1;
  }
}
