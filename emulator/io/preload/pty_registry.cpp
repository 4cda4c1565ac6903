#include "io/preload/pty_registry.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace dxlemu::preload {
namespace {

// How long a device number found for a path is trusted for a descriptor that matches it.
constexpr long kRefreshIntervalNs = 1000000000L;
constexpr long kNsPerSecond = 1000000000L;

// Holds the mutex for a scope; the library has no exceptions, so this is only for the early
// returns.
class Lock {
 public:
  explicit Lock(pthread_mutex_t& mutex) : mutex_(mutex) { pthread_mutex_lock(&mutex_); }
  ~Lock() { pthread_mutex_unlock(&mutex_); }
  Lock(const Lock&) = delete;
  Lock& operator=(const Lock&) = delete;

 private:
  pthread_mutex_t& mutex_;
};

long ns_since(const timespec& then, const timespec& now) {
  return (now.tv_sec - then.tv_sec) * kNsPerSecond + (now.tv_nsec - then.tv_nsec);
}

// One line on stderr, with write(2): stdio may not be usable where the client calls us.
void warn(const char* text) {
  constexpr const char* kPrefix = "dxlemu-preload: ";
  constexpr const char* kSuffix = "; no descriptor is treated as a dxlemu port\n";
  const char* const parts[] = {kPrefix, text, kSuffix};
  for (const char* part : parts) {
    const std::size_t length = std::strlen(part);
    if (::write(STDERR_FILENO, part, length) != static_cast<ssize_t>(length)) {
      return;
    }
  }
}

// PtyRegistry needs no constructor: constant-initialised, it exists before any code runs.
constinit PtyRegistry registry;

}  // namespace

PtyRegistry& PtyRegistry::instance() {
  return registry;
}

dev_t PtyRegistry::character_device(int fd) {
  struct stat status {};
  if (::fstat(fd, &status) != 0 || !S_ISCHR(status.st_mode)) {
    return 0;
  }
  return status.st_rdev;
}

bool PtyRegistry::is_dxlemu_pty(int fd) {
  const dev_t rdev = character_device(fd);
  if (rdev == 0) {
    return false;
  }
  Lock lock(mutex_);
  return is_listed_locked(rdev);
}

bool PtyRegistry::emulate(int fd, unsigned long request, void* arg, int& result) {
  const dev_t rdev = character_device(fd);
  if (rdev == 0) {
    return false;
  }
  Lock lock(mutex_);
  if (!is_listed_locked(rdev)) {
    return false;
  }
  // The kernel checks CAP_SYS_ADMIN; root stands for it here.
  result = emulate_serial_ioctl(device_locked(rdev).state, request, arg, ::geteuid() == 0);
  return true;
}

void PtyRegistry::load_list_locked() {
  loaded_ = true;
  const char* text = std::getenv("DXLEMU_PTYS");
  const PtyListError error = parse_pty_list(text, list_);
  if (error != PtyListError::None) {
    warn(pty_list_error_text(error));
  } else if (list_.count == 0) {
    warn("DXLEMU_PTYS is not set or names no path");
  }
}

void PtyRegistry::refresh_locked() {
  for (std::size_t i = 0; i < list_.count; ++i) {
    struct stat status {};
    const bool is_device = ::stat(list_.paths[i], &status) == 0 && S_ISCHR(status.st_mode);
    listed_[i] = is_device ? status.st_rdev : 0;
  }
  ::clock_gettime(CLOCK_MONOTONIC, &refreshed_);
}

bool PtyRegistry::is_listed_locked(dev_t rdev) {
  if (!loaded_) {
    load_list_locked();
    refresh_locked();
  }
  const auto listed = [this, rdev] {
    for (std::size_t i = 0; i < list_.count; ++i) {
      if (listed_[i] == rdev) {
        return true;
      }
    }
    return false;
  };
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  if (listed() && ns_since(refreshed_, now) < kRefreshIntervalNs) {
    return true;
  }
  refresh_locked();
  return listed();
}

PtyRegistry::Device& PtyRegistry::device_locked(dev_t rdev) {
  for (std::size_t i = 0; i < device_count_; ++i) {
    if (devices_[i].rdev == rdev) {
      return devices_[i];
    }
  }
  std::size_t slot = device_count_;
  if (device_count_ < kMaxDevices) {
    ++device_count_;
  } else {
    slot = next_forgotten_;
    next_forgotten_ = (next_forgotten_ + 1) % kMaxDevices;
  }
  devices_[slot] = Device{rdev, initial_serial_device()};
  return devices_[slot];
}

}  // namespace dxlemu::preload
