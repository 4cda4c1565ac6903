#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/servo.hpp"

namespace dxlemu::test {

/// A Write instruction of item `key` = `value` to `servo` in its own protocol, as the bus
/// delivers it (little-endian, the item's size); returns the status error byte.
inline std::uint8_t bus_write(model::Servo& servo, const std::string& key, std::int64_t value) {
  const model::ItemSpec& item = *servo.spec().find(key);
  std::vector<std::uint8_t> data;
  for (std::size_t i = 0; i < item.size; ++i) {
    data.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i)));
  }
  const wire::InstructionPacket packet{servo.protocol().value_or(wire::Protocol::V2), servo.id(),
                                       wire::Write{item.address, data}};
  return servo.execute(packet, model::Addressing::Unicast).error;
}

}  // namespace dxlemu::test
