#pragma once

#include <pthread.h>
#include <sys/types.h>
#include <time.h>

#include <cstddef>

#include "io/preload/pty_list.hpp"
#include "io/preload/serial_device.hpp"

namespace dxlemu::preload {

/// Whether a descriptor is one of dxlemu's pseudo-terminals (a path of DXLEMU_PTYS, links
/// followed), and the emulated serial state of each such device. One per process, behind one
/// mutex; every function may be called from any thread, before main or after exit began (no
/// constructor, no destructor, no allocation).
///
/// A descriptor is ours when it is a character device whose device number is that of a listed
/// path. The paths' device numbers are looked up again when a descriptor matches none of them
/// (a daemon started after the client, a port re-created) and at least once a second otherwise
/// (a port that went away no longer claims its old number).
class PtyRegistry {
 public:
  /// The process's registry (zero-initialised storage, filled on first use).
  static PtyRegistry& instance();

  /// True when `fd` is one of dxlemu's PTYs now.
  bool is_dxlemu_pty(int fd);

  /// When `fd` is one of dxlemu's PTYs, answers `request` (is_emulated_request) on its device's
  /// state, stores the result (0 or an errno value) in `result` and returns true; else returns
  /// false and leaves `result` alone.
  bool emulate(int fd, unsigned long request, void* arg, int& result);

 private:
  /// The most devices whose state is kept; the oldest is forgotten beyond that.
  static constexpr std::size_t kMaxDevices = kMaxPtyPaths;

  struct Device {
    dev_t rdev;
    SerialDevice state;
  };
  // The character device `fd` is, or 0 (not a character device, or fstat failed).
  static dev_t character_device(int fd);
  // With the mutex held: whether `rdev` is a listed path's device, refreshing as described.
  bool is_listed_locked(dev_t rdev);
  void load_list_locked();
  void refresh_locked();
  Device& device_locked(dev_t rdev);

  pthread_mutex_t mutex_ = PTHREAD_MUTEX_INITIALIZER;
  bool loaded_ = false;
  PtyList list_{};
  dev_t listed_[kMaxPtyPaths]{};  // each path's device now; 0 while it names none
  timespec refreshed_{};          // CLOCK_MONOTONIC of the last refresh
  Device devices_[kMaxDevices]{};
  std::size_t device_count_ = 0;
  std::size_t next_forgotten_ = 0;
};

}  // namespace dxlemu::preload
