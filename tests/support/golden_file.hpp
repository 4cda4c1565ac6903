#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "wire/protocol.hpp"

namespace dxlemu::test {

/// One example packet from the e-Manual, as written in tests/data/golden_packets.txt.
struct GoldenPacket {
  std::string name;
  std::string source;  ///< page and section it comes from
  wire::Protocol protocol = wire::Protocol::V2;
  std::string kind;  ///< "instruction", "status" or "fast_reply"
  std::vector<std::uint8_t> bytes;
  std::string expect;                                ///< describe() of the decoded packet
  std::vector<std::uint16_t> lengths;                ///< fast_reply: data length of each block
  std::optional<std::vector<std::uint8_t>> printed;  ///< bytes as misprinted on the page
};

/// Reads and validates the golden file; throws std::runtime_error naming the line on a bad entry.
std::vector<GoldenPacket> load_golden_packets(const std::string& path);

/// The golden file of this checkout (tests/data/golden_packets.txt).
std::vector<GoldenPacket> load_golden_packets();

/// The golden packets of one protocol, in file order.
std::vector<GoldenPacket> load_golden_packets(wire::Protocol protocol);

/// The bytes of `packets` back to back.
std::vector<std::uint8_t> concatenated(const std::vector<GoldenPacket>& packets);

}  // namespace dxlemu::test
