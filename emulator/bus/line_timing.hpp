#pragma once

#include <cstddef>
#include <cstdint>

#include "sim/sim_time.hpp"

namespace dxlemu::bus {

/// Time `bytes` take on the line at `bps` with 8N1 framing (10 bits per byte), rounded up to the
/// nanosecond. A PTY delivers a write at once, so the bus models the line itself (DESIGN.md
/// "Time").
sim::SimDuration wire_time(std::size_t bytes, std::uint32_t bps);

/// True when a servo listening at `servo_bps` can decode a client sending at `client_bps`: the
/// rates differ by at most 3 % (a UART samples mid-bit; beyond a few percent over 10 bits the
/// stop bit is missed). Otherwise the servo hears noise and stays silent.
bool baud_matches(std::uint32_t client_bps, std::uint32_t servo_bps);

}  // namespace dxlemu::bus
