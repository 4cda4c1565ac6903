#pragma once

#include <chrono>
#include <optional>

namespace dxlemu::io {

/// How long the calling thread has waited, runnable, for a CPU: the second figure of Linux's
/// /proc/thread-self/schedstat (run-queue wait, ns), read through a descriptor kept open.
///
/// The daemon marks it at the end of every handler; when bytes then arrive, the wait since the
/// mark is how long the thread, woken by them, stood in the run queue before it could read them,
/// so the bytes are that much older than the read (docs/timing.md "Late replies").
class CpuWait {
 public:
  /// Opens the calling thread's schedstat; without one (a kernel without CONFIG_SCHED_INFO),
  /// since_mark() is always zero.
  CpuWait();
  ~CpuWait();
  CpuWait(const CpuWait&) = delete;
  CpuWait& operator=(const CpuWait&) = delete;

  /// Whether the kernel gives the figure.
  bool available() const { return fd_ >= 0; }
  /// Remembers the present total wait.
  void mark();
  /// The wait since the last mark() (zero before the first).
  std::chrono::nanoseconds since_mark() const;

 private:
  std::optional<std::chrono::nanoseconds> read_total() const;

  int fd_ = -1;
  std::optional<std::chrono::nanoseconds> marked_;
};

}  // namespace dxlemu::io
