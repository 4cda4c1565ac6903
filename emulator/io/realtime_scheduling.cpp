#include "io/realtime_scheduling.hpp"

#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace dxlemu::io {

RealtimeScheduling request_realtime_scheduling(int priority) {
  RealtimeScheduling result;
  sched_param param{};
  param.sched_priority = priority;
  // sched_setscheduler(0, ...) acts on the calling thread on Linux, which is the thread that
  // runs the io_context; threads made later inherit it.
  if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
    result.fifo = true;
    result.message = "SCHED_FIFO at priority " + std::to_string(priority);
  } else {
    const int error = errno;
    result.message = "SCHED_FIFO at priority " + std::to_string(priority) + " refused (" +
                     std::strerror(error) +
                     (error == EPERM ? "; permit it with CAP_SYS_NICE, e.g. `sudo setcap "
                                       "cap_sys_nice,cap_ipc_lock+ep $(command -v dxlemu)`, or "
                                       "an rtprio limit in /etc/security/limits.conf"
                                     : "") +
                     ")";
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    result.locked = true;
    result.message += ", memory locked";
  } else {
    const int error = errno;
    result.message +=
        ", memory lock refused (" + std::string(std::strerror(error)) +
        (error == EPERM || error == ENOMEM ? "; permit it with CAP_IPC_LOCK or a memlock limit in "
                                             "/etc/security/limits.conf"
                                           : "") +
        ")";
  }
  if (!result.fifo || !result.locked) {
    result.message += "; running with what was granted";
  }
  return result;
}

}  // namespace dxlemu::io
