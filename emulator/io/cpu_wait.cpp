#include "io/cpu_wait.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <charconv>
#include <string_view>

namespace dxlemu::io {

CpuWait::CpuWait() : fd_(::open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC)) {
  if (fd_ >= 0 && !read_total()) {
    ::close(fd_);
    fd_ = -1;
  }
}

CpuWait::~CpuWait() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

std::optional<std::chrono::nanoseconds> CpuWait::read_total() const {
  if (fd_ < 0) {
    return std::nullopt;
  }
  // "RUN_NS WAIT_NS SLICES\n": three numbers, well under 64 bytes.
  std::array<char, 96> text{};
  const ssize_t n = ::pread(fd_, text.data(), text.size() - 1, 0);
  if (n <= 0) {
    return std::nullopt;
  }
  const std::string_view line(text.data(), static_cast<std::size_t>(n));
  const std::size_t space = line.find(' ');
  if (space == std::string_view::npos) {
    return std::nullopt;
  }
  long long wait = 0;
  const char* first = line.data() + space + 1;
  const auto [end, ec] = std::from_chars(first, line.data() + line.size(), wait);
  if (ec != std::errc{} || end == first) {
    return std::nullopt;
  }
  return std::chrono::nanoseconds{wait};
}

void CpuWait::mark() {
  if (fd_ >= 0) {
    marked_ = read_total();
  }
}

std::chrono::nanoseconds CpuWait::since_mark() const {
  if (!marked_) {
    return std::chrono::nanoseconds{0};
  }
  const auto total = read_total();
  return total && *total > *marked_ ? *total - *marked_ : std::chrono::nanoseconds{0};
}

}  // namespace dxlemu::io
