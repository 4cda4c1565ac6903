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
  /// already passed (the instruction was read late). Returns false when the link dropped them
  /// instead (the client is not reading: docs/bus.md "Statistics").
  virtual bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at) = 0;

  /// The line rate, in bit/s with 8N1 framing, of the bytes the following deliver() calls carry,
  /// so that a link can tell when each byte arrived (`at` minus the wire time of the bytes after
  /// it); 0 when they take no wire time (ReplyTiming::Immediate). The bus sets it before every
  /// deliver(). Links that only care about whole deliveries ignore it.
  virtual void set_line_rate(std::uint32_t /*bps*/) {}
};

}  // namespace dxlemu::bus
