// TCGETS2 lives in <asm/termbits.h>, which clashes with glibc's <termios.h>; this file includes
// only the kernel header so that the rest of io/ can use <termios.h>.
#include "io/tty_baud.hpp"

#include <asm/termbits.h>
#include <sys/ioctl.h>

namespace dxlemu::io {

std::uint32_t tty_baud(int fd) {
  struct termios2 t {};
  if (ioctl(fd, TCGETS2, &t) != 0) {
    return 0;
  }
  return heard_baud(t.c_cflag, t.c_ospeed);
}

std::uint32_t heard_baud(unsigned cflag, std::uint32_t ospeed) {
  // A parity bit lands where the servo expects the stop bit, and 7-bit characters are shorter
  // than the servo's: either way what it hears is noise, as from a client at another rate.
  if ((cflag & PARENB) != 0 || (cflag & CSIZE) != CS8) {
    return 0;
  }
  // The client sets the speed it transmits at; a PTY carries it without effect on timing.
  return ospeed;
}

}  // namespace dxlemu::io
