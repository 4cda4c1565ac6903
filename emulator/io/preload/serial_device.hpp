#pragma once

#include <linux/serial.h>

namespace dxlemu::preload {

/// What a USB serial adapter's driver keeps for one device and a pseudo-terminal does not: the
/// serial settings of TIOCGSERIAL/TIOCSSERIAL, the modem-control lines and the RS-485 settings.
/// The values are those Linux's ftdi_sio driver reports for the FT232H of a ROBOTIS U2D2
/// (docs/exec.md lists them).
struct SerialDevice {
  serial_struct serial;
  int modem_lines;  ///< TIOCM_* bits
  serial_rs485 rs485;
};

/// A device as the driver has it when the port is first opened: ASYNC flags clear (16 ms latency
/// timer), baud_base 60 MHz, DTR and RTS raised, no input line asserted, RS-485 off.
SerialDevice initial_serial_device();

/// True for the requests `emulate_serial_ioctl` answers: TIOCGSERIAL, TIOCSSERIAL, TIOCMGET,
/// TIOCMSET, TIOCMBIS, TIOCMBIC, TIOCGRS485, TIOCSRS485.
bool is_emulated_request(unsigned long request);

/// Answers `request` (one `is_emulated_request` accepts) on `device` with `arg`, the ioctl's
/// third argument, as the driver would: returns 0, or the errno value of the failure (EFAULT for
/// a null `arg`; EPERM for a TIOCSSERIAL that changes more than the user flags, or the close
/// delays, when not `privileged`; EINVAL for any other request).
int emulate_serial_ioctl(SerialDevice& device, unsigned long request, void* arg, bool privileged);

}  // namespace dxlemu::preload
