#pragma once

#include <cstdint>
#include <span>

#include "sim/sim_time.hpp"

namespace dxlemu::bus {

/// Where a bus sends bytes to the client: the PTY in the daemon (io/), a recorder in tests.
class ByteLink {
 public:
  ByteLink() = default;
  ByteLink(const ByteLink&) = delete;
  ByteLink& operator=(const ByteLink&) = delete;
  virtual ~ByteLink() = default;

  /// Hands `bytes` to the client at simulated time `at`, the moment their last byte would have
  /// arrived on a real line. Called from a scheduler event, at `at`, or at once when `at` had
  /// already passed (the instruction was read late). `bps` is the line rate the bytes crossed
  /// the line at, in bit/s with 8N1 framing, so that a link can tell when each byte arrived (`at`
  /// minus the wire time of the bytes after it); 0 when they took no wire time
  /// (ReplyTiming::Immediate). Links that only care about whole deliveries ignore it. Returns
  /// false when the link dropped them instead (the client is not reading: docs/bus.md
  /// "Statistics").
  virtual bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at, std::uint32_t bps) = 0;
};

}  // namespace dxlemu::bus
