#pragma once

#include <sys/types.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dxlemu::bench {

/// `dxlemu run ARGS` (or any program that prints readiness lines as dxlemu does) as a child
/// process, started and waited for (its readiness lines read); SIGTERM and wait when destroyed.
/// Its stderr is the bench's.
class Daemon {
 public:
  /// Starts `binary` with `args` (after "run") and reads `ports` readiness lines (one per port).
  /// Throws when it cannot start or prints no readiness line within 30 s.
  Daemon(const std::string& binary, const std::vector<std::string>& args, std::size_t ports = 1);
  /// Starts the program `command[0]` with the arguments `command[1...]` as they are (no "run"
  /// added), e.g. a stand-in for dxlemu such as bench/pty_echo, and reads `ports` readiness
  /// lines. Throws as above.
  explicit Daemon(std::vector<std::string> command, std::size_t ports = 1);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// The readiness lines, one per port in config order.
  const std::vector<nlohmann::json>& ready() const { return ready_; }
  /// The PTY of port `index` (the "pty" of its readiness line).
  std::string pty(std::size_t index = 0) const;
  /// The daemon's process id (for /proc/PID figures).
  pid_t pid() const { return pid_; }
  /// SIGTERM, then waits; returns the exit status (as waitpid gives it). Idempotent.
  int stop();

 private:
  pid_t pid_ = 0;
  int stdout_ = -1;
  bool stopped_ = false;
  std::vector<nlohmann::json> ready_;
};

/// CPU time (user + system) process `pid` has used so far, from /proc/PID/stat.
std::chrono::nanoseconds cpu_time(pid_t pid);

/// The peak resident set size of process `pid` in KiB (VmHWM of /proc/PID/status).
long peak_rss_kib(pid_t pid);

/// CPU time process `pid`'s threads have run so far, to the ns: the sum of the first field of
/// /proc/PID/task/*/schedstat. cpu_time() counts clock ticks (10 ms each at USER_HZ 100), too
/// coarse to tell an idle process from one that wakes a few hundred times a second.
std::chrono::nanoseconds run_time(pid_t pid);

/// The number of `field` in /proc/PID/status (e.g. "voluntary_ctxt_switches", "VmRSS" in KiB);
/// -1 when the field is missing.
long proc_status_number(pid_t pid, const std::string& field);

}  // namespace dxlemu::bench
