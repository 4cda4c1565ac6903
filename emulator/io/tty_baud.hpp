#pragma once

#include <cstdint>

namespace dxlemu::io {

/// The bit rate the terminal `fd` is set to, read with TCGETS2 so that any rate works, including
/// BOTHER rates such as 4.5 Mbit/s that the classic termios speeds cannot express. 0 if unknown.
std::uint32_t tty_baud(int fd);

}  // namespace dxlemu::io
