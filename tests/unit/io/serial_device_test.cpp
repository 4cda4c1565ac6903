// The serial, modem-line and RS-485 requests the preload library answers on a dxlemu PTY as
// Linux's ftdi_sio driver does for a U2D2's FT232H (docs/exec.md "What the library answers").
#include <linux/serial.h>
#include <sys/ioctl.h>

#include <catch2/catch.hpp>
#include <cerrno>

#include "io/preload/serial_device.hpp"

using namespace dxlemu::preload;

namespace {

serial_struct read_serial(SerialDevice& device) {
  serial_struct serial{};
  REQUIRE(emulate_serial_ioctl(device, TIOCGSERIAL, &serial, false) == 0);
  return serial;
}

int modem_lines(SerialDevice& device) {
  int lines = -1;
  REQUIRE(emulate_serial_ioctl(device, TIOCMGET, &lines, false) == 0);
  return lines;
}

}  // namespace

TEST_CASE("A new device reports an FT232H at 60 MHz with no flags and DTR and RTS raised",
          "[preload]") {
  SerialDevice device = initial_serial_device();
  const serial_struct serial = read_serial(device);
  CHECK(serial.type == PORT_UNKNOWN);
  CHECK(serial.baud_base == 60000000);
  CHECK(serial.flags == 0);
  CHECK(serial.xmit_fifo_size == 0);
  CHECK(serial.close_delay == 50);
  CHECK(serial.closing_wait == 3000);
  CHECK(modem_lines(device) == (TIOCM_DTR | TIOCM_RTS));
}

TEST_CASE("ASYNC_LOW_LATENCY set by a user is read back, the hardware facts are not changed",
          "[preload]") {
  SerialDevice device = initial_serial_device();
  serial_struct wanted = read_serial(device);
  wanted.flags |= ASYNC_LOW_LATENCY;
  wanted.baud_base = 1;
  wanted.xmit_fifo_size = 99;
  CHECK(emulate_serial_ioctl(device, TIOCSSERIAL, &wanted, false) == 0);
  const serial_struct serial = read_serial(device);
  CHECK(serial.flags == ASYNC_LOW_LATENCY);
  CHECK(serial.baud_base == 60000000);
  CHECK(serial.xmit_fifo_size == 0);
}

TEST_CASE("Only a privileged caller may change flags beyond the user's or the close delays",
          "[preload]") {
  SerialDevice device = initial_serial_device();
  serial_struct wanted = read_serial(device);
  wanted.flags |= ASYNC_HUP_NOTIFY;
  CHECK(emulate_serial_ioctl(device, TIOCSSERIAL, &wanted, false) == EPERM);
  wanted = read_serial(device);
  wanted.closing_wait = ASYNC_CLOSING_WAIT_NONE;
  CHECK(emulate_serial_ioctl(device, TIOCSSERIAL, &wanted, false) == EPERM);
  CHECK(read_serial(device).closing_wait == 3000);
  CHECK(emulate_serial_ioctl(device, TIOCSSERIAL, &wanted, true) == 0);
  CHECK(read_serial(device).closing_wait == ASYNC_CLOSING_WAIT_NONE);
}

TEST_CASE("TIOCMSET, TIOCMBIS and TIOCMBIC change DTR and RTS only", "[preload]") {
  SerialDevice device = initial_serial_device();
  int lines = TIOCM_RTS | TIOCM_CTS;
  CHECK(emulate_serial_ioctl(device, TIOCMBIC, &lines, false) == 0);
  CHECK(modem_lines(device) == TIOCM_DTR);
  CHECK(emulate_serial_ioctl(device, TIOCMBIS, &lines, false) == 0);
  CHECK(modem_lines(device) == (TIOCM_DTR | TIOCM_RTS));
  lines = TIOCM_RTS | TIOCM_CD;
  CHECK(emulate_serial_ioctl(device, TIOCMSET, &lines, false) == 0);
  CHECK(modem_lines(device) == TIOCM_RTS);
}

TEST_CASE("The RS-485 settings are kept as set", "[preload]") {
  SerialDevice device = initial_serial_device();
  serial_rs485 rs485{};
  CHECK(emulate_serial_ioctl(device, TIOCGRS485, &rs485, false) == 0);
  CHECK(rs485.flags == 0);
  rs485.flags = SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND;
  rs485.delay_rts_before_send = 2;
  CHECK(emulate_serial_ioctl(device, TIOCSRS485, &rs485, false) == 0);
  serial_rs485 back{};
  CHECK(emulate_serial_ioctl(device, TIOCGRS485, &back, false) == 0);
  CHECK(back.flags == (SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND));
  CHECK(back.delay_rts_before_send == 2);
}

TEST_CASE("A null argument is EFAULT and a request not emulated is EINVAL", "[preload]") {
  SerialDevice device = initial_serial_device();
  CHECK(emulate_serial_ioctl(device, TIOCGSERIAL, nullptr, false) == EFAULT);
  int value = 0;
  CHECK(emulate_serial_ioctl(device, FIONREAD, &value, false) == EINVAL);
  CHECK(is_emulated_request(TIOCSSERIAL));
  CHECK(is_emulated_request(TIOCSRS485));
  CHECK_FALSE(is_emulated_request(TCFLSH));
  CHECK_FALSE(is_emulated_request(FIONREAD));
}
