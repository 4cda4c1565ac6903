#include "modbus_seed_frames.hpp"

#include <string>

#include "wire/hex.hpp"
#include "wire/modbus_codec.hpp"

namespace dxlemu::test {
namespace modbus_seed {

std::vector<std::uint8_t> hex(std::string_view text) {
  return wire::parse_hex(text).value();
}

// A frame from `address` with `function` and `data`, its CRC computed.
std::vector<std::uint8_t> frame(std::uint8_t address, std::uint8_t function,
                                const std::vector<std::uint8_t>& data) {
  return wire::encode_modbus_frame(address, function, data);
}

// Write Multiple Registers (0x10) of `count` registers from `start`, or Read/Write Multiple
// Registers (0x17) reading 2 registers from 0x0080 first: the values count up.
std::vector<std::uint8_t> write_many(std::uint8_t function, std::uint16_t start,
                                     std::uint8_t count) {
  std::vector<std::uint8_t> data;
  if (function == 0x17) {
    data = {0x00, 0x80, 0x00, 0x02};
  }
  data.insert(data.end(),
              {static_cast<std::uint8_t>(start >> 8), static_cast<std::uint8_t>(start & 0xFFU),
               0x00, count, static_cast<std::uint8_t>(count * 2)});
  for (std::uint8_t i = 0; i < count * 2; ++i) {
    data.push_back(i);
  }
  return frame(1, function, data);
}

}  // namespace modbus_seed

const std::vector<ModbusSeedFrame>& modbus_seed_frames() {
  using modbus_seed::frame;
  using modbus_seed::hex;
  using modbus_seed::write_many;
  constexpr std::uint8_t kMaxWriteRegisters = 123;
  constexpr std::uint8_t kMaxReadWriteRegisters = 121;
  constexpr std::size_t kLongestEcho = 250;  // a 256-byte frame: address, 08, 00 00, data, CRC
  static const std::vector<ModbusSeedFrame> frames = [&] {
    std::vector<std::uint8_t> echo = {0x00, 0x00};
    for (std::size_t i = 0; i < kLongestEcho; ++i) {
      echo.push_back(static_cast<std::uint8_t>(i));
    }
    return std::vector<ModbusSeedFrame>{
        // modbus-rtu.md "Frames (computed)".
        {"read_10_from_0", hex("01 03 00 00 00 0A C5 CD")},
        {"spec_request", hex("11 03 00 6B 00 03 76 87")},
        {"spec_response", hex("11 03 06 02 2B 00 00 00 64 C8 BA")},
        {"read_model_number", hex("01 03 00 00 00 02 C4 0B")},
        {"read_goal_position", hex("01 03 01 1A 00 02 E4 30")},
        {"torque_enable", hex("01 06 01 00 00 01 49 F6")},
        {"goal_position_2048", hex("01 10 01 1A 00 02 04 08 00 00 00 7D 2C")},
        {"exception_illegal_address", hex("01 83 02 C0 F1")},
        // Every function a DYNAMIXEL server answers.
        {"read_input_registers", frame(1, 0x04, hex("00 00 00 02"))},
        {"diagnostics_query_data", frame(1, 0x08, hex("00 00 12 34"))},
        {"write_multiple_one_register", write_many(0x10, 0x0100, 1)},
        {"read_write_multiple", write_many(0x17, 0x0100, 1)},
        // Functions and a sub-function it does not serve (exception 01).
        {"diagnostics_restart", frame(1, 0x08, hex("00 01 00 00"))},
        {"read_coils", frame(1, 0x01, hex("00 00 00 08"))},
        {"read_device_identification", frame(1, 0x2B, hex("0E 01 00"))},
        // Malformed requests: quantity 0 and 126, a byte count that is not twice the quantity,
        // a data field too short, registers beyond 16-bit byte addresses.
        {"read_quantity_0", frame(1, 0x03, hex("00 00 00 00"))},
        {"read_quantity_126", frame(1, 0x03, hex("00 00 00 7E"))},
        {"write_byte_count_mismatch", frame(1, 0x10, hex("01 00 00 02 02 00 01"))},
        {"read_short", frame(1, 0x03, hex("00 00 00"))},
        {"read_beyond_byte_addresses", frame(1, 0x03, hex("7F FF 00 02"))},
        // The longest requests, and a 256-byte frame.
        {"write_multiple_123", write_many(0x10, 0x0000, kMaxWriteRegisters)},
        {"read_write_multiple_121", write_many(0x17, 0x0000, kMaxReadWriteRegisters)},
        {"diagnostics_256_bytes", frame(1, 0x08, echo)},
        // Broadcast (never answered) and the highest address.
        {"broadcast_write", frame(0, 0x06, hex("01 00 00 00"))},
        {"address_247", frame(247, 0x03, hex("00 00 00 01"))},
    };
  }();
  return frames;
}

}  // namespace dxlemu::test
