#include "faults/packet_mangling.hpp"

#include <algorithm>
#include <span>

#include "wire/checksum.hpp"
#include "wire/crc16.hpp"
#include "wire/crc16_modbus.hpp"

namespace dxlemu::faults {

void break_check(std::vector<std::uint8_t>& packet) {
  if (!packet.empty()) {
    packet.back() = static_cast<std::uint8_t>(~packet.back());
  }
}

void flip_bits(std::vector<std::uint8_t>& bytes, std::uint32_t bits, sim::RandomStream& stream) {
  const std::uint64_t total = bytes.size() * 8;
  if (total <= bits) {
    for (auto& b : bytes) {
      b = static_cast<std::uint8_t>(~b);
    }
    return;
  }
  std::vector<std::uint64_t> chosen;
  while (chosen.size() < bits) {
    const std::uint64_t bit = stream.uniform(0, total - 1);
    if (std::find(chosen.begin(), chosen.end(), bit) == chosen.end()) {
      chosen.push_back(bit);
      bytes[bit / 8] ^= static_cast<std::uint8_t>(1U << (bit % 8));
    }
  }
}

void set_id(std::vector<std::uint8_t>& packet, wire::Protocol protocol, std::uint8_t id) {
  if (wire::traits(protocol).frame.check == wire::CheckKind::Crc16Modbus) {
    // ADDRESS FUNCTION DATA... CRC_L CRC_H (Modbus RTU): the address is the first byte.
    constexpr std::size_t kShortest = 4;
    if (packet.size() < kShortest) {
      return;
    }
    packet[0] = id;
    const std::uint16_t crc = wire::crc16_modbus({packet.data(), packet.size() - 2});
    packet[packet.size() - 2] = static_cast<std::uint8_t>(crc & 0xFF);
    packet[packet.size() - 1] = static_cast<std::uint8_t>(crc >> 8);
    return;
  }
  if (wire::has_v1_layout(protocol)) {
    // FF FF ID LEN ERR PARAM... CHECKSUM (1.0 and FEETECH)
    if (packet.size() < 6) {
      return;
    }
    packet[2] = id;
    const std::span<const std::uint8_t> body(packet.data() + 2, packet.size() - 3);
    packet.back() = wire::v1_checksum(body);
    return;
  }
  // FF FF FD 00 ID LEN_L LEN_H INST ... CRC_L CRC_H
  if (packet.size() < 10) {
    return;
  }
  packet[4] = id;
  const std::uint16_t crc = wire::crc16({packet.data(), packet.size() - 2});
  packet[packet.size() - 2] = static_cast<std::uint8_t>(crc & 0xFF);
  packet[packet.size() - 1] = static_cast<std::uint8_t>(crc >> 8);
}

std::vector<std::uint8_t> random_bytes(std::size_t count, sim::RandomStream& stream) {
  std::vector<std::uint8_t> out(count);
  for (auto& b : out) {
    b = static_cast<std::uint8_t>(stream.uniform(0, 0xFF));
  }
  return out;
}

}  // namespace dxlemu::faults
