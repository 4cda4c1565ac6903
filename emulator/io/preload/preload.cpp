// libdxlemu-preload.so: loaded into a client with LD_PRELOAD (by `dxlemu exec`, docs/exec.md),
// it makes dxlemu's pseudo-terminals behave as a USB serial adapter where a PTY cannot:
//   - tcflush(TCOFLUSH) keeps what was written: on an adapter those bytes are already on the wire,
//     on a PTY they may still wait for the daemon to read them and would be lost;
//   - TIOCGSERIAL/TIOCSSERIAL, the modem-control lines and the RS-485 settings answer as an
//     FTDI adapter's driver, instead of failing with ENOTTY.
// Every other descriptor and request goes to libc untouched.
//
// Both tcflush and ioctl are interposed: glibc's tcflush calls the kernel through its internal
// ioctl, which LD_PRELOAD cannot reach, and a client may call ioctl(TCFLSH) itself. Neither path
// calls the other here, and the rewrite (TCOFLUSH -> nothing, TCIOFLUSH -> TCIFLUSH) gives the
// same result if a libc ever routed one through the other.
#include <dlfcn.h>
#include <pthread.h>
#include <sys/ioctl.h>
#include <termios.h>

#include <cerrno>
#include <cstdarg>
#include <cstdint>

#include "io/preload/pty_registry.hpp"
#include "io/preload/serial_device.hpp"

namespace {

using IoctlFunction = int (*)(int, unsigned long, ...);
using TcflushFunction = int (*)(int, int);

IoctlFunction real_ioctl = nullptr;
TcflushFunction real_tcflush = nullptr;
pthread_once_t resolved = PTHREAD_ONCE_INIT;

void resolve() {
  real_ioctl = reinterpret_cast<IoctlFunction>(::dlsym(RTLD_NEXT, "ioctl"));
  real_tcflush = reinterpret_cast<TcflushFunction>(::dlsym(RTLD_NEXT, "tcflush"));
}

// The queue a flush of `queue` must empty on a dxlemu PTY, or -1 for none.
int queue_to_flush(int queue) {
  switch (queue) {
    case TCOFLUSH:
      return -1;
    case TCIOFLUSH:
      return TCIFLUSH;
    default:
      return queue;
  }
}

bool rewrites(int queue) {
  return queue == TCOFLUSH || queue == TCIOFLUSH;
}

}  // namespace

/// libc's tcflush, but on a dxlemu PTY TCOFLUSH does nothing and TCIOFLUSH flushes input only.
extern "C" __attribute__((visibility("default"))) int tcflush(int fd, int queue) noexcept {
  pthread_once(&resolved, resolve);
  if (real_tcflush == nullptr) {
    errno = ENOSYS;
    return -1;
  }
  if (rewrites(queue) && dxlemu::preload::PtyRegistry::instance().is_dxlemu_pty(fd)) {
    queue = queue_to_flush(queue);
    if (queue < 0) {
      return 0;
    }
  }
  return real_tcflush(fd, queue);
}

/// libc's ioctl, but on a dxlemu PTY TCFLSH is rewritten as tcflush above and the serial,
/// modem-line and RS-485 requests are answered from the device's emulated state.
extern "C" __attribute__((visibility("default"))) int ioctl(int fd, unsigned long request,
                                                            ...) noexcept {
  // Every ioctl takes at most one argument, an integer or a pointer: pass it on as glibc does.
  va_list args;
  va_start(args, request);
  void* arg = va_arg(args, void*);
  va_end(args);
  pthread_once(&resolved, resolve);
  if (real_ioctl == nullptr) {
    errno = ENOSYS;
    return -1;
  }
  auto& registry = dxlemu::preload::PtyRegistry::instance();
  if (request == TCFLSH) {
    // The queue is an int passed by value: only the low 32 bits of the register are defined.
    int queue = static_cast<int>(reinterpret_cast<std::uintptr_t>(arg));
    if (rewrites(queue) && registry.is_dxlemu_pty(fd)) {
      queue = queue_to_flush(queue);
      if (queue < 0) {
        return 0;
      }
      return real_ioctl(fd, request, queue);
    }
  } else if (dxlemu::preload::is_emulated_request(request)) {
    int result = 0;
    if (registry.emulate(fd, request, arg, result)) {
      if (result != 0) {
        errno = result;
        return -1;
      }
      return 0;
    }
  }
  return real_ioctl(fd, request, arg);
}
