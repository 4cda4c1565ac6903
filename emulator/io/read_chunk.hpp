#pragma once

#include <cstddef>

namespace dxlemu::io {

/// Bytes asked of one read() from a PTY or a socket: a burst of packets or of JSON lines comes in
/// one call, and what is left waits for the next readiness.
inline constexpr std::size_t kReadChunk = 4096;

}  // namespace dxlemu::io
