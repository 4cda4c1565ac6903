#include "io/preload/serial_device.hpp"

#include <sys/ioctl.h>

#include <cerrno>
#include <cstring>

namespace dxlemu::preload {
namespace {

// ftdi_sio's baud_base for the Hi-Speed chips (FT232H, FT2232H, FT4232H): 120 MHz / 2.
constexpr int kFtdiHighSpeedBaudBase = 120000000 / 2;
// usb-serial reports the tty port's default delays in hundredths of a second: 0.5 s and 30 s.
constexpr unsigned short kCloseDelay = 50;
constexpr unsigned short kClosingWait = 3000;
// ftdi_sio changes only these two outputs on TIOCMSET/TIOCMBIS/TIOCMBIC.
constexpr int kModemOutputs = TIOCM_DTR | TIOCM_RTS;

int set_serial(SerialDevice& device, const serial_struct& wanted, bool privileged) {
  serial_struct& serial = device.serial;
  // ftdi_sio: without CAP_SYS_ADMIN only the user flags (ASYNC_USR_MASK: the speed hack and
  // ASYNC_LOW_LATENCY) may change; usb-serial: likewise the close delays.
  if (!privileged &&
      (((wanted.flags ^ serial.flags) & ~ASYNC_USR_MASK) != 0 ||
       wanted.close_delay != serial.close_delay || wanted.closing_wait != serial.closing_wait)) {
    return EPERM;
  }
  serial.flags = wanted.flags & static_cast<int>(ASYNC_FLAGS);
  serial.custom_divisor = wanted.custom_divisor;
  serial.close_delay = wanted.close_delay;
  serial.closing_wait = wanted.closing_wait;
  return 0;
}

}  // namespace

SerialDevice initial_serial_device() {
  SerialDevice device{};
  // type PORT_UNKNOWN, line 0 (ttyUSB0), no FIFO size: what usb-serial leaves unset.
  device.serial.baud_base = kFtdiHighSpeedBaudBase;
  device.serial.close_delay = kCloseDelay;
  device.serial.closing_wait = kClosingWait;
  // The tty layer raises DTR and RTS when the port is opened at a non-zero rate.
  device.modem_lines = kModemOutputs;
  return device;
}

bool is_emulated_request(unsigned long request) {
  switch (request) {
    case TIOCGSERIAL:
    case TIOCSSERIAL:
    case TIOCMGET:
    case TIOCMSET:
    case TIOCMBIS:
    case TIOCMBIC:
    case TIOCGRS485:
    case TIOCSRS485:
      return true;
    default:
      return false;
  }
}

int emulate_serial_ioctl(SerialDevice& device, unsigned long request, void* arg, bool privileged) {
  if (arg == nullptr) {
    return EFAULT;
  }
  switch (request) {
    case TIOCGSERIAL:
      std::memcpy(arg, &device.serial, sizeof(device.serial));
      return 0;
    case TIOCSSERIAL: {
      serial_struct wanted{};
      std::memcpy(&wanted, arg, sizeof(wanted));
      return set_serial(device, wanted, privileged);
    }
    case TIOCMGET:
      std::memcpy(arg, &device.modem_lines, sizeof(device.modem_lines));
      return 0;
    case TIOCMSET:
    case TIOCMBIS:
    case TIOCMBIC: {
      int lines = 0;
      std::memcpy(&lines, arg, sizeof(lines));
      lines &= kModemOutputs;
      int& state = device.modem_lines;
      if (request == TIOCMSET) {
        state = (state & ~kModemOutputs) | lines;
      } else if (request == TIOCMBIS) {
        state |= lines;
      } else {
        state &= ~lines;
      }
      return 0;
    }
    case TIOCGRS485:
      std::memcpy(arg, &device.rs485, sizeof(device.rs485));
      return 0;
    case TIOCSRS485:
      std::memcpy(&device.rs485, arg, sizeof(device.rs485));
      return 0;
    default:
      return EINVAL;
  }
}

}  // namespace dxlemu::preload
