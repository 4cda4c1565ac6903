#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "wire/instruction.hpp"
#include "wire/status.hpp"

namespace dxlemu::scan {

/// The client side of a bus as a scan uses it: an instruction out, the status packets that come
/// back. io/serial_scan_link.hpp is the serial device's; tests use an emulated bus.
class ScanLink {
 public:
  virtual ~ScanLink() = default;
  /// Sets the rate the link sends and receives at.
  virtual void set_baud(std::uint32_t bps) = 0;
  /// Sends `packet` and returns the status packets of its protocol that come back, in order of
  /// arrival: once `max_replies` have come, or once no byte has arrived for `timeout` (after the
  /// send, or after the last byte).
  virtual std::vector<wire::StatusPacket> exchange(const wire::InstructionPacket& packet,
                                                   std::size_t max_replies,
                                                   std::chrono::microseconds timeout) = 0;
};

}  // namespace dxlemu::scan
