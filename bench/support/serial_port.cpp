// The client's baud is set with TCSETS2/BOTHER, so any rate works; that needs <asm/termbits.h>,
// which clashes with <termios.h>, so this file includes only the kernel's header.
#include "support/serial_port.hpp"

#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace dxlemu::bench {

void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

int open_port(const std::string& path, std::uint32_t bps) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    fail("opening " + path);
  }
  termios2 t{};
  if (ioctl(fd, TCGETS2, &t) != 0) {
    fail("TCGETS2");
  }
  // What cfmakeraw does, with the kernel's struct.
  t.c_iflag &= ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON);
  t.c_oflag &= ~OPOST;
  t.c_lflag &= ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
  t.c_cflag &= ~(CSIZE | PARENB | CBAUD | CRTSCTS);
  t.c_cflag |= CS8 | CREAD | CLOCAL | BOTHER;
  t.c_ispeed = bps;
  t.c_ospeed = bps;
  if (ioctl(fd, TCSETS2, &t) != 0) {
    fail("TCSETS2");
  }
  ioctl(fd, TCFLSH, TCIOFLUSH);
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
  ioctl(fd, TCFLSH, TCIFLUSH);
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
