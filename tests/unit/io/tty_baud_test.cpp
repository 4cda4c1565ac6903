// The client's serial settings as the daemon reads them off the PTY: its speed, and whether a
// servo's 8N1 UART could decode its characters at all (docs/bus.md).
#include <catch2/catch.hpp>

#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include "io/tty_baud.hpp"

namespace dxlemu::test::tty_baud {

TEST_CASE("8 data bits without parity are heard at their speed, two stop bits too", "[io][tty]") {
  CHECK(io::heard_baud(CS8 | CREAD, 57600) == 57600);
  CHECK(io::heard_baud(CS8 | CSTOPB | CREAD, 1'000'000) == 1'000'000);
}

TEST_CASE("Parity or 7-bit characters are noise to a servo, as another speed is", "[io][tty]") {
  CHECK(io::heard_baud(CS8 | PARENB, 57600) == 0);
  CHECK(io::heard_baud(CS8 | PARENB | PARODD, 57600) == 0);
  CHECK(io::heard_baud(CS7, 57600) == 0);
}

TEST_CASE("A PTY's speed set by the client is read back", "[io][tty]") {
  int master = -1;
  int slave = -1;
  REQUIRE(openpty(&master, &slave, nullptr, nullptr, nullptr) == 0);
  termios t{};
  REQUIRE(tcgetattr(slave, &t) == 0);
  cfmakeraw(&t);
  cfsetspeed(&t, B57600);
  REQUIRE(tcsetattr(slave, TCSANOW, &t) == 0);
  CHECK(io::tty_baud(slave) == 57600);
  close(slave);
  close(master);
}

}  // namespace dxlemu::test::tty_baud
