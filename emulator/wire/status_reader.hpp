#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sim/sim_time.hpp"
#include "wire/framer.hpp"
#include "wire/status.hpp"

namespace dxlemu::wire {

/// Turns the bytes a client receives into the status packets of one protocol's framing;
/// anything else (garbage, collided bytes, packets that are no status) is dropped.
class StatusReader {
 public:
  explicit StatusReader(Protocol protocol) : framer_(protocol) {}
  /// Consumes `bytes` that arrived at `at` and appends the status packets they complete.
  void feed(std::span<const std::uint8_t> bytes, sim::SimTime at, std::vector<StatusPacket>& out);

 private:
  Framer framer_;
  std::vector<FramerEvent> events_;
};

}  // namespace dxlemu::wire
