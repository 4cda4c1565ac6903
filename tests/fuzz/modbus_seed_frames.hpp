#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace dxlemu::test {

/// One Modbus RTU frame the fuzz seeds start from.
struct ModbusSeedFrame {
  std::string_view name;  ///< what it is, as a file name
  std::vector<std::uint8_t> bytes;
};

/// The frames of modbus-rtu.md "Frames (computed)" (requests, a response and an exception),
/// then a request of every function a DYNAMIXEL server answers and of some it does not,
/// malformed requests of each kind the decoder refuses, the longest requests, broadcast and
/// the highest address.
const std::vector<ModbusSeedFrame>& modbus_seed_frames();

}  // namespace dxlemu::test
