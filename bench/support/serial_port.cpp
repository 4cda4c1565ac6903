// The client's port is set raw, at any rate, by io/raw_serial.
#include "support/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "io/raw_serial.hpp"

namespace dxlemu::bench {

void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

int open_port(const std::string& path, std::uint32_t bps) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    fail("opening " + path);
  }
  io::set_raw_serial(fd, bps, path);
  return fd;
}

std::optional<Clock::time_point> read_exactly(int fd, std::span<std::uint8_t> out,
                                              Clock::time_point give_up) {
  std::size_t got = 0;
  while (got < out.size()) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(give_up - Clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      return std::nullopt;
    }
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno != EINTR && errno != EAGAIN) {
      fail("read");
    }
    got += n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  return Clock::now();
}

void flush_input(int fd) {
  io::discard_input(fd);
}

void pin_to_cpu(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (sched_setaffinity(0, sizeof(set), &set) != 0) {
    fail("pinning to CPU " + std::to_string(cpu));
  }
}

std::vector<Arrival> read_arrivals(int fd, std::span<std::uint8_t> out, Clock::time_point give_up) {
  std::vector<Arrival> arrivals;
  std::size_t got = 0;
  while (got < out.size()) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(give_up - Clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      break;
    }
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno != EINTR && errno != EAGAIN) {
      fail("read");
    }
    if (n > 0) {
      got += static_cast<std::size_t>(n);
      arrivals.push_back({got, Clock::now()});
    }
  }
  return arrivals;
}

}  // namespace dxlemu::bench
