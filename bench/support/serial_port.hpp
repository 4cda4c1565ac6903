#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dxlemu::bench {

using Clock = std::chrono::steady_clock;

/// Throws std::system_error with errno and `what`.
[[noreturn]] void fail(const std::string& what);

/// Opens the client side of a serial port (a PTY) raw at `bps` (8N1, no flow control, any rate
/// through TCSETS2/BOTHER), non-blocking, input and output flushed. Throws on failure.
int open_port(const std::string& path, std::uint32_t bps);

/// Reads exactly `out.size()` bytes from `fd`, waiting in poll(2) as a blocking serial client
/// does. Returns the time the last read() returned, or nullopt when `give_up` passed first.
std::optional<Clock::time_point> read_exactly(int fd, std::span<std::uint8_t> out,
                                              Clock::time_point give_up);

/// Discards whatever `fd` has received and not yet read.
void flush_input(int fd);

/// Restricts this process, and the processes it starts later, to CPU `cpu`.
void pin_to_cpu(int cpu);

/// One read() that returned data: how many bytes had arrived in all once it returned, and when.
struct Arrival {
  std::size_t total = 0;
  Clock::time_point at;
};

/// Reads into `out` until it is full or `give_up` passes, waiting in poll(2) as read_exactly
/// does, and returns every read() that returned data, in order: the last one's `total` is how
/// many bytes arrived, and the times show when each part of a long answer (a chain of replies)
/// came in.
std::vector<Arrival> read_arrivals(int fd, std::span<std::uint8_t> out, Clock::time_point give_up);

}  // namespace dxlemu::bench
