// The rate is set with TCSETS2/BOTHER, so any rate works; that needs <asm/termbits.h>, which
// clashes with <termios.h>, so this file includes only the kernel's header.
#include "io/raw_serial.hpp"

#include <asm/termbits.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <system_error>

namespace dxlemu::io {

void set_raw_serial(int fd, std::uint32_t bps, const std::string& what) {
  termios2 t{};
  if (ioctl(fd, TCGETS2, &t) != 0) {
    throw std::system_error(errno, std::generic_category(),
                            what + ": not a serial device (TCGETS2)");
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
    throw std::system_error(errno, std::generic_category(),
                            what + ": cannot set " + std::to_string(bps) + " bps");
  }
  ioctl(fd, TCFLSH, TCIOFLUSH);
}

void discard_input(int fd) {
  ioctl(fd, TCFLSH, TCIFLUSH);
}

}  // namespace dxlemu::io
