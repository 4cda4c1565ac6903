// pcap captures (docs/pcap.md): the global header and records, byte for byte, with damaged packets
// recorded from the bytes their framing errors carry.
#include <catch2/catch.hpp>
#include <sstream>

#include "app/record/pcap_writer.hpp"
#include "pcap_layout.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

namespace {

using test::pcap::kGlobalHeaderBytes;
using test::pcap::kRecordHeaderBytes;

// 2023-11-14 22:13:20.25 UTC, as microseconds since the Unix epoch.
constexpr std::chrono::microseconds kStart{1'700'000'000'250'000};

Bytes bytes_of(const std::ostringstream& out) {
  const std::string text = out.str();
  return {text.begin(), text.end()};
}

std::uint32_t le32(const Bytes& b, std::size_t at) {
  return b[at] | (b[at + 1] << 8U) | (b[at + 2] << 16U) |
         (static_cast<std::uint32_t>(b[at + 3]) << 24U);
}

// The records after the global header: each one's pseudo-header and line bytes.
std::vector<Bytes> records(const Bytes& file) {
  std::vector<Bytes> out;
  for (std::size_t at = kGlobalHeaderBytes; at < file.size();) {
    const std::uint32_t captured = le32(file, at + 8);
    const auto begin = file.begin() + static_cast<std::ptrdiff_t>(at + kRecordHeaderBytes);
    out.emplace_back(begin, begin + captured);
    at += kRecordHeaderBytes + captured;
  }
  return out;
}

Bytes with_pseudo_header(std::uint8_t direction, std::uint8_t protocol, std::uint8_t port,
                         const Bytes& line) {
  Bytes out = {app::kPcapPseudoHeaderVersion, direction, protocol, port};
  out.reserve(out.size() + line.size());
  out.insert(out.end(), line.begin(), line.end());
  return out;
}

// What the bus does: the client's bytes go to the framer, whose events (garbage aside, which the
// bus only counts) reach the writer's heard().
void hear(app::PcapWriter& writer, wire::Framer& framer, const Bytes& bytes, sim::SimTime at) {
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, at, events);
  for (const auto& event : events) {
    const auto* failure = std::get_if<wire::FramingError>(&event);
    if (failure == nullptr || failure->kind != wire::FramingErrorKind::Garbage) {
      writer.heard(0, event);
    }
  }
}

}  // namespace

TEST_CASE("A capture starts with the classic pcap global header for LINKTYPE_USER0",
          "[app][pcap]") {
  std::ostringstream out;
  const app::PcapWriter writer(out, kStart);
  CHECK(bytes_of(out) == Bytes{0xD4, 0xC3, 0xB2, 0xA1,    // magic: microsecond timestamps
                               0x02, 0x00, 0x04, 0x00,    // version 2.4
                               0x00, 0x00, 0x00, 0x00,    // thiszone
                               0x00, 0x00, 0x00, 0x00,    // sigfigs
                               0x00, 0x00, 0x04, 0x00,    // snaplen 262144
                               0x93, 0x00, 0x00, 0x00});  // LINKTYPE_USER0 (147)
}

TEST_CASE("A packet heard is a record stamped with the start plus simulated time in microseconds",
          "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  wire::Framer framer(wire::Protocol::V2);
  const Bytes read = wire::encode_instruction({wire::Protocol::V2, 1, wire::Read{132, 4}});
  // 1.5 ms and 999 ns after the start: the nanoseconds are cut, not rounded.
  hear(writer, framer, read, sim::SimTime{} + 1500us + 999ns);
  const Bytes file = bytes_of(out);
  const Bytes expected_record = {
      0x00, 0xF1, 0x53, 0x65,  // 1700000000 s
      0x6C, 0xD6, 0x03, 0x00,  // 251500 µs
      0x12, 0x00, 0x00, 0x00,  // 18 bytes captured
      0x12, 0x00, 0x00, 0x00,  // of 18
      0x01, 0x00, 0x02, 0x00,  // v1 pseudo-header, client to servos, 2.0, port 0
      0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x02,  // the Read of protocol2.md
      0x84, 0x00, 0x04, 0x00, 0x1D, 0x15};
  REQUIRE(file.size() == kGlobalHeaderBytes + expected_record.size());
  CHECK(Bytes(file.begin() + kGlobalHeaderBytes, file.end()) == expected_record);
}

TEST_CASE("A reply sent is a servos-to-client record with its protocol and port index",
          "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  const Bytes status = wire::encode_status({wire::Protocol::V1, 5, 0x20, {}});
  writer.sent(3, status, sim::SimTime{} + 2s, wire::Protocol::V1);
  writer.sent(300, status, sim::SimTime{} + 2s, wire::Protocol::V1);
  const Bytes file = bytes_of(out);
  CHECK(le32(file, kGlobalHeaderBytes) == 1'700'000'002);
  CHECK(le32(file, kGlobalHeaderBytes + 4) == 250'000);
  CHECK(records(file) ==
        std::vector<Bytes>{with_pseudo_header(1, 1, 3, status),
                           with_pseudo_header(1, 1, app::kPcapPortOverflow, status)});
}

TEST_CASE("A bad CRC packet is recorded with its bytes", "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  wire::Framer framer(wire::Protocol::V2);
  const Bytes ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  Bytes bad = wire::encode_instruction({wire::Protocol::V2, 2, wire::Read{132, 4}});
  bad.back() ^= 0xFF;
  Bytes line = {0x00, 0xFF, 0x13};  // garbage first, which is not recorded
  line.insert(line.end(), bad.begin(), bad.end());
  line.insert(line.end(), ping.begin(), ping.end());
  hear(writer, framer, line, sim::SimTime{});
  CHECK(records(bytes_of(out)) ==
        std::vector<Bytes>{with_pseudo_header(0, 2, 0, bad), with_pseudo_header(0, 2, 0, ping)});
}

TEST_CASE("A truncated packet is recorded with the bytes that arrived", "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  wire::Framer framer(wire::Protocol::V1);
  const Bytes ping = wire::encode_instruction({wire::Protocol::V1, 7, wire::Ping{}});
  const Bytes partial(ping.begin(), ping.end() - 2);
  hear(writer, framer, partial, sim::SimTime{});
  hear(writer, framer, ping, sim::SimTime{} + 1s);  // after the 100 ms inter-byte timeout
  CHECK(records(bytes_of(out)) == std::vector<Bytes>{with_pseudo_header(0, 1, 0, partial),
                                                     with_pseudo_header(0, 1, 0, ping)});
}

TEST_CASE("A header with an impossible length is recorded as far as it goes", "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  wire::Framer framer(wire::Protocol::V2);
  const Bytes header = {0xFF, 0xFF, 0xFD, 0x00, 0x03, 0xFF, 0xFF};  // LENGTH 65535
  const Bytes ping = wire::encode_instruction({wire::Protocol::V2, 3, wire::Ping{}});
  Bytes line = header;
  line.insert(line.end(), ping.begin(), ping.end());
  hear(writer, framer, line, sim::SimTime{});
  CHECK(records(bytes_of(out)) ==
        std::vector<Bytes>{with_pseudo_header(0, 2, 0, header), with_pseudo_header(0, 2, 0, ping)});
}

TEST_CASE("Garbage between packets is not recorded, even when it is reported", "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  wire::Framer framer(wire::Protocol::V1);
  const Bytes ping = wire::encode_instruction({wire::Protocol::V1, 2, wire::Ping{}});
  Bytes line = {0x00, 0x13, 0x37};
  line.insert(line.end(), ping.begin(), ping.end());
  std::vector<wire::FramerEvent> events;
  framer.feed(line, sim::SimTime{}, events);
  REQUIRE(events.size() == 2);
  for (const auto& event : events) {
    writer.heard(0, event);
  }
  CHECK(records(bytes_of(out)) == std::vector<Bytes>{with_pseudo_header(0, 1, 0, ping)});
}

TEST_CASE("A delivery longer than the snap length is cut with its full length kept",
          "[app][pcap]") {
  std::ostringstream out;
  app::PcapWriter writer(out, kStart);
  const Bytes noise(app::kPcapSnapLength, 0xAA);
  writer.sent(0, noise, sim::SimTime{}, wire::Protocol::V2);
  const Bytes file = bytes_of(out);
  CHECK(le32(file, kGlobalHeaderBytes + 8) == app::kPcapSnapLength);
  CHECK(le32(file, kGlobalHeaderBytes + 12) == app::kPcapSnapLength + app::kPcapPseudoHeaderBytes);
  CHECK(file.size() == kGlobalHeaderBytes + kRecordHeaderBytes + app::kPcapSnapLength);
}
