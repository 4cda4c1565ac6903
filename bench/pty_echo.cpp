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
// With --reply-after-us N it is the bare *timed* responder instead: each status is written N µs
// after the read() that completed its instruction returned, waited for with one absolute
// clock_nanosleep (and the timer slack set to 1 ns, as dxlemu sets it). That is the least a
// process that answers at a modelled time can do: one sleep for the instruction, one for the
// reply. reply_latency --echo measures dxlemu's CPU per reply against it.
//
// Usage: pty_echo [--reply-after-us N]
#include <fcntl.h>
#include <stdlib.h>  // NOLINT(modernize-deprecated-headers): posix_openpt and friends are POSIX
#include <sys/prctl.h>
#include <termios.h>
#include <time.h>  // NOLINT(modernize-deprecated-headers): clock_nanosleep is POSIX
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
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

// Sleeps until `delay` after `from` on CLOCK_MONOTONIC (steady_clock's clock), through signals.
void sleep_until(timespec from, std::chrono::nanoseconds delay) {
  constexpr long kNsPerSecond = 1'000'000'000;
  const long long total = static_cast<long long>(from.tv_nsec) + delay.count();
  timespec due{from.tv_sec + static_cast<time_t>(total / kNsPerSecond), total % kNsPerSecond};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, nullptr) == EINTR) {
  }
}

// The N of --reply-after-us N, or nullopt without the option.
std::optional<std::chrono::microseconds> parse_delay(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  if (args.empty()) {
    return std::nullopt;
  }
  if (args.size() != 2 || args[0] != "--reply-after-us") {
    throw std::invalid_argument("usage: pty_echo [--reply-after-us N]");
  }
  const std::string value(args[1]);
  char* end = nullptr;
  const long long us = std::strtoll(value.c_str(), &end, 10);
  if (end == value.c_str() || *end != '\0' || us < 0) {
    throw std::invalid_argument("--reply-after-us needs a number of microseconds, not \"" + value +
                                "\"");
  }
  return std::chrono::microseconds{us};
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

int main(int argc, char** argv) {
  try {
    const auto delay = parse_delay(argc, argv);
    if (delay) {
      prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    }
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
      timespec read_at{};
      clock_gettime(CLOCK_MONOTONIC, &read_at);
      for (pending += n > 0 ? static_cast<std::size_t>(n) : 0; pending >= instruction_size;
           pending -= instruction_size) {
        if (delay) {
          sleep_until(read_at, *delay);
        }
        write_all(master, status);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "pty_echo: " << e.what() << "\n";
    return 1;
  }
}
