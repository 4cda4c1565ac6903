#pragma once

#include <string>

namespace dxlemu::io {

/// What asking for real-time scheduling gave.
struct RealtimeScheduling {
  bool fifo = false;    ///< the calling thread runs under SCHED_FIFO
  bool locked = false;  ///< every page of the process is locked in memory
  /// One line for the log: what was set, or what the system refused and how to permit it.
  std::string message;
};

/// Puts the calling thread under SCHED_FIFO at `priority` (1 ~ 99) and locks the process's
/// memory (mlockall, present and future pages), so that neither other processes' time slices nor
/// page faults delay a reply. Each is best effort: what is refused (no CAP_SYS_NICE or
/// RLIMIT_RTPRIO; no CAP_IPC_LOCK or too small RLIMIT_MEMLOCK) is said in the message, and the
/// daemon goes on with normal scheduling.
RealtimeScheduling request_realtime_scheduling(int priority);

}  // namespace dxlemu::io
