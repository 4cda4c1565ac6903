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
  /// The line is taken to be silent from here on: a frame of a silence-delimited protocol (Modbus
  /// RTU) still being read ends now, and its status is appended. A master that cannot time the
  /// line's silences (bytes read in chunks off a USB adapter) ends its frames this way.
  void end_of_write(std::vector<StatusPacket>& out);

 private:
  void decode(std::vector<StatusPacket>& out);

  Framer framer_;
  std::vector<FramerEvent> events_;
};

}  // namespace dxlemu::wire
