// The Protocol 2.0 CRC-16 and the Protocol 1.0 checksum.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>

#include "wire/checksum.hpp"
#include "wire/crc16.hpp"

using namespace dxlemu;

namespace {

// A bit-at-a-time CRC straight from the definition (poly 0x8005, MSB first, init 0): an
// independent implementation to check the table-driven one against.
std::uint16_t bitwise_crc(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0;
  for (const std::uint8_t b : bytes) {
    crc ^= static_cast<std::uint16_t>(b << 8);
    for (int i = 0; i < 8; ++i) {
      crc = static_cast<std::uint16_t>((crc & 0x8000U) != 0 ? (crc << 1) ^ 0x8005U : crc << 1);
    }
  }
  return crc;
}

}  // namespace

TEST_CASE("The CRC table equals the one printed in protocol2-crc.md", "[wire][crc]") {
  const auto& table = wire::crc16_table();
  const std::filesystem::path page =
      std::filesystem::path(DXLEMU_REFERENCE_DIR) / "protocol2-crc.md";
  INFO("the reference (../shared/reference beside the checkout) has the page: " << page);
  REQUIRE(std::filesystem::exists(page));
  // Rows look like "| 0x08 | 0x8033 | 0x0036 | ... |": a row start, then eight entries.
  std::ifstream in(page);
  const std::regex row(R"(^\| 0x([0-9A-F]{2}) \|((?: 0x[0-9A-F]{4} \|){8})\s*$)");
  const std::regex entry(R"(0x([0-9A-F]{4}))");
  std::string line;
  std::size_t compared = 0;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, row)) {
      continue;
    }
    std::size_t index = std::stoul(m[1].str(), nullptr, 16);
    const std::string entries = m[2].str();
    for (std::sregex_iterator it(entries.begin(), entries.end(), entry), end; it != end; ++it) {
      INFO("entry 0x" << std::hex << index);
      CHECK(table.at(index) == std::stoul((*it)[1].str(), nullptr, 16));
      ++index;
      ++compared;
    }
  }
  CHECK(compared == 256);
}

TEST_CASE("The table-driven CRC matches a bitwise CRC and can be fed in pieces", "[wire][crc]") {
  std::vector<std::uint8_t> bytes;
  for (unsigned i = 0; i < 300; ++i) {
    bytes.push_back(static_cast<std::uint8_t>(i * 37 + 11));
  }
  for (std::size_t n = 0; n <= bytes.size(); n += 7) {
    const auto prefix = std::span(bytes).first(n);
    CHECK(wire::crc16(prefix) == bitwise_crc(prefix));
    const std::size_t half = n / 2;
    CHECK(wire::crc16_update(wire::crc16(prefix.first(half)), prefix.subspan(half)) ==
          wire::crc16(prefix));
  }
}

TEST_CASE("The CRC page's worked example: Read 2 bytes from address 0 of ID 1", "[wire][crc]") {
  // protocol2-crc.md "CRC Calculation Example": the CRC covers the first 12 bytes (5 + LENGTH 7).
  const std::vector<std::uint8_t> packet = {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07,
                                            0x00, 0x02, 0x00, 0x00, 0x02, 0x00};
  CHECK(wire::crc16(packet) == bitwise_crc(packet));
  CHECK(wire::crc16(packet) == 0x5121);
}

TEST_CASE("The 1.0 checksum is the complement of the byte sum, low byte only", "[wire][checksum]") {
  // protocol1.md "Checksum (Instruction Packet)": ~(0x01+0x05+0x03+0x0C+0x64+0xAA) = ~0x123 ->
  // 0xDC.
  const std::vector<std::uint8_t> body = {0x01, 0x05, 0x03, 0x0C, 0x64, 0xAA};
  CHECK(wire::v1_checksum(body) == 0xDC);
  // protocol1.md "Error": FF FF 01 02 24 D8.
  CHECK(wire::v1_checksum(std::vector<std::uint8_t>{0x01, 0x02, 0x24}) == 0xD8);
  CHECK(wire::v1_checksum({}) == 0xFF);
}
