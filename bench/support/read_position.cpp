#include "support/read_position.hpp"

#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::bench {

std::vector<std::uint8_t> read_position_instruction(std::uint8_t id) {
  return wire::encode_instruction(
      {wire::Protocol::V2, id, wire::Read{kPresentPosition, kPresentPositionSize}});
}

std::vector<std::uint8_t> read_position_status(std::uint8_t id, std::int32_t position) {
  constexpr unsigned kBitsPerByte = 8;
  std::vector<std::uint8_t> value;
  const auto bits = static_cast<std::uint32_t>(position);  // two's complement, as on the wire
  for (unsigned i = 0; i < kPresentPositionSize; ++i) {
    value.push_back(static_cast<std::uint8_t>(bits >> (kBitsPerByte * i)));
  }
  return wire::encode_status({wire::Protocol::V2, id, 0, value});
}

}  // namespace dxlemu::bench
