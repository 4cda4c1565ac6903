#pragma once

#include <vector>

#include "bus/byte_link.hpp"

namespace dxlemu::bus {

/// A ByteLink that records every delivery, for tests on the virtual clock.
class LoopbackLink : public ByteLink {
 public:
  /// One delivery: the bytes and the simulated time they reached the client.
  struct Delivery {
    std::vector<std::uint8_t> bytes;
    sim::SimTime at{};
    bool operator==(const Delivery&) const = default;
  };

  bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at,
               std::uint32_t /*bps*/) override {
    if (!accepting_) {
      return false;
    }
    deliveries_.push_back({{bytes.begin(), bytes.end()}, at});
    return true;
  }

  /// While false, deliveries are refused, as by a client that stopped reading.
  void set_accepting(bool accepting) { accepting_ = accepting; }

  /// Everything delivered so far, in order.
  const std::vector<Delivery>& deliveries() const { return deliveries_; }
  /// Forgets what was delivered.
  void clear() { deliveries_.clear(); }

 private:
  std::vector<Delivery> deliveries_;
  bool accepting_ = true;
};

}  // namespace dxlemu::bus
