#pragma once

#include <cstdint>
#include <string>

namespace dxlemu::io {

/// Sets the serial device `fd` raw, 8N1, no flow control, at `bps` (any rate: TCSETS2/BOTHER),
/// and discards whatever it held both ways, as a servo client opens its port. Throws
/// std::system_error naming `what` (the device) when the device refuses.
void set_raw_serial(int fd, std::uint32_t bps, const std::string& what);

/// Discards whatever the serial device `fd` has received and not yet been read.
void discard_input(int fd);

}  // namespace dxlemu::io
