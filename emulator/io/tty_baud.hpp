#pragma once

#include <cstdint>

namespace dxlemu::io {

/// The bit rate the terminal `fd` is set to, read with TCGETS2 so that any rate works, including
/// BOTHER rates such as 4.5 Mbit/s that the classic termios speeds cannot express. 0 if unknown,
/// and 0 too when its characters are not 8 data bits without parity: a servo's UART, which takes
/// 8N1 (a second stop bit is only a longer idle), cannot decode them (docs/bus.md "Baud rate
/// and character format").
std::uint32_t tty_baud(int fd);

/// What tty_baud() makes of a terminal's control flags `cflag` (termios `c_cflag`) and output
/// speed `ospeed`: the speed, or 0 when the characters are not 8 data bits without parity.
std::uint32_t heard_baud(unsigned cflag, std::uint32_t ospeed);

}  // namespace dxlemu::io
