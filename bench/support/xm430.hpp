#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>

// What every bench assumes of the servos it talks to (XM430-W350 at factory settings but the
// baud rate) and of a client's patience.
namespace dxlemu::bench {

/// models/xm430-w350.json "timing": ping_us, read_us and write_us are 50 (no per-byte cost).
constexpr std::chrono::microseconds kProcessing{50};
/// Factory Return Delay Time of the XM430-W350: item value 250 × 2 µs (control table address 9).
constexpr std::chrono::microseconds kReturnDelay{500};
/// The X series' Present Position: control table address 132, 4 bytes (e-Manual XM430-W350).
constexpr std::uint16_t kPresentPosition = 132;
constexpr std::uint16_t kPresentPositionSize = 4;
/// A Ping status carries the model number (2 bytes) and the firmware version.
constexpr std::size_t kPingParams = 3;

/// How long a client waits for a reply (or the rest of a chain) beyond its modelled time before
/// counting it lost.
constexpr std::chrono::milliseconds kReplyTimeout{100};
/// After a lost or bad reply, how long to let stray bytes arrive before discarding them.
constexpr std::chrono::milliseconds kSettle{20};
/// A write() of a few hundred bytes to a PTY takes a few µs. When it takes longer, the client was
/// preempted inside it, the moment the bytes reached the emulator is unknown (the reply may even
/// arrive before write() returns), and the round trip is skipped and counted, not timed.
constexpr std::chrono::microseconds kMaxWriteTime{100};

}  // namespace dxlemu::bench
