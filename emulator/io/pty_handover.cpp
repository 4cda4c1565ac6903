#include "io/pty_handover.hpp"

#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <vector>

namespace dxlemu::io {

namespace {

using Clock = std::chrono::steady_clock;

// The size of a Read instruction, and a pause between round trips like a controller's (the
// kernel's hand-over is slower from idle than back to back).
constexpr std::size_t kPacket = 14;
constexpr std::chrono::microseconds kPause{300};
constexpr int kPollTimeoutMs = 100;
// Somewhat more than an idle machine takes both ways (about 35 µs on the 2-CPU VM of
// docs/benchmarks.md): under load the measurement runs high, and replies would come early.
constexpr std::chrono::microseconds kMaxHandover{60};

// Moves one packet from `from` to `to`; false when it did not arrive in time.
bool hand_over(int from, int to) {
  std::array<unsigned char, kPacket> packet{};
  if (::write(from, packet.data(), packet.size()) != static_cast<ssize_t>(packet.size())) {
    return false;
  }
  std::size_t got = 0;
  while (got < packet.size()) {
    pollfd p{to, POLLIN, 0};
    if (poll(&p, 1, kPollTimeoutMs) <= 0) {
      return false;
    }
    const ssize_t n = ::read(to, packet.data(), packet.size() - got);
    if (n <= 0) {
      return false;
    }
    got += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

std::chrono::nanoseconds measure_pty_handover(int samples) {
  int master = -1;
  int slave = -1;
  if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) {
    return {};
  }
  termios raw{};
  tcgetattr(slave, &raw);
  cfmakeraw(&raw);
  tcsetattr(slave, TCSANOW, &raw);
  std::vector<std::chrono::nanoseconds> round_trips;
  for (int i = 0; i < samples; ++i) {
    usleep(static_cast<useconds_t>(kPause.count()));
    const Clock::time_point start = Clock::now();
    if (!hand_over(slave, master) || !hand_over(master, slave)) {
      break;
    }
    round_trips.push_back(Clock::now() - start);
  }
  ::close(slave);
  ::close(master);
  if (round_trips.empty()) {
    return {};
  }
  // The first quartile rather than the median: a daemon starting on a busy machine (a CI job
  // starting it among other tests) would otherwise take the load of that moment for the PTY's
  // own delay, and then answer early. Capped for the same reason.
  const auto quartile = round_trips.begin() + static_cast<std::ptrdiff_t>(round_trips.size() / 4);
  std::nth_element(round_trips.begin(), quartile, round_trips.end());
  return std::min<std::chrono::nanoseconds>(*quartile, kMaxHandover);
}

}  // namespace dxlemu::io
