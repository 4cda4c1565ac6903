// Protocol 2.0 byte stuffing (protocol2.md "Packet Process"): FF FF FD inside a packet becomes
// FF FF FD FD, LENGTH counts the stuffed bytes, the CRC covers the stuffed packet, and Fast
// Sync/Bulk Read replies are never stuffed.
#include <catch2/catch.hpp>

#include <algorithm>

#include "framer_events.hpp"
#include "wire/crc16.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"
#include "wire/stuffing.hpp"

using namespace dxlemu;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

wire::InstructionPacket write_of(Bytes data) {
  return {Protocol::V2, 1, wire::Write{0x0074, std::move(data)}};
}

// Frames and decodes one encoded packet; it must come out as exactly one frame.
std::size_t length_field(const Bytes& packet) {
  return packet[5] | (packet[6] << 8);
}

}  // namespace

TEST_CASE("Stuffing inserts FD after every FF FF FD and unstuffing removes it",
          "[wire][stuffing]") {
  struct Case {
    Bytes plain;
    Bytes stuffed;
  };
  const std::vector<Case> cases = {
      {{0x01, 0x02}, {0x01, 0x02}},
      {{0xFF, 0xFF, 0xFD}, {0xFF, 0xFF, 0xFD, 0xFD}},                          // at the end
      {{0x03, 0xFF, 0xFF, 0xFD, 0x04}, {0x03, 0xFF, 0xFF, 0xFD, 0xFD, 0x04}},  // inside
      {{0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD},                                   // repeated
       {0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD}},
      {{0xFF, 0xFF, 0xFD, 0xFD}, {0xFF, 0xFF, 0xFD, 0xFD, 0xFD}},  // already looks stuffed
      {{0xFF, 0xFF, 0xFF, 0xFD}, {0xFF, 0xFF, 0xFF, 0xFD, 0xFD}},
      {{0xFF, 0xFD, 0xFF, 0xFF}, {0xFF, 0xFD, 0xFF, 0xFF}},
  };
  for (const auto& c : cases) {
    CHECK(wire::stuff(c.plain) == c.stuffed);
    CHECK(wire::unstuff(c.stuffed) == c.plain);
  }
}

TEST_CASE("Unstuffing keeps a bare FF FF FD from a sender that did not stuff", "[wire][stuffing]") {
  CHECK(wire::unstuff(Bytes{0xFF, 0xFF, 0xFD, 0x01}) == Bytes{0xFF, 0xFF, 0xFD, 0x01});
}

TEST_CASE("A Write whose data holds FF FF FD is stuffed, LENGTH counts the stuffing, CRC covers it",
          "[wire][stuffing]") {
  for (const Bytes& data : {Bytes{0xFF, 0xFF, 0xFD, 0x00}, Bytes{0x00, 0xFF, 0xFF, 0xFD},
                            Bytes{0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD}}) {
    const auto packet = write_of(data);
    const Bytes bytes = wire::encode_instruction(packet);
    std::size_t patterns = 0;
    for (std::size_t i = 2; i < data.size(); ++i) {
      patterns += data[i - 2] == 0xFF && data[i - 1] == 0xFF && data[i] == 0xFD ? 1 : 0;
    }
    // LENGTH = instruction + address (2) + data + stuffed bytes + CRC (2).
    CHECK(length_field(bytes) == 1 + 2 + data.size() + patterns + 2);
    CHECK(bytes.size() == 7 + length_field(bytes));
    const std::uint16_t crc = wire::crc16(std::span(bytes).first(bytes.size() - 2));
    CHECK(bytes[bytes.size() - 2] == (crc & 0xFF));
    CHECK(bytes[bytes.size() - 1] == (crc >> 8));
    // The framer finds no header inside the stuffed data and decodes the original data.
    const auto decoded = wire::decode_instruction(test::frame_one(Protocol::V2, bytes));
    REQUIRE(std::holds_alternative<wire::InstructionPacket>(decoded));
    CHECK(std::get<wire::InstructionPacket>(decoded) == packet);
  }
}

TEST_CASE("A stuffed packet split inside its stuffing still frames", "[wire][stuffing]") {
  const Bytes bytes = wire::encode_instruction(write_of({0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFD}));
  // Both patterns went out stuffed, so that some cuts below fall inside the stuffing.
  const Bytes stuffed{0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xFF, 0xFD, 0xFD};
  REQUIRE(std::search(bytes.begin(), bytes.end(), stuffed.begin(), stuffed.end()) != bytes.end());
  for (std::size_t cut = 1; cut < bytes.size(); ++cut) {
    wire::Framer framer(Protocol::V2);
    std::vector<wire::FramerEvent> events;
    framer.feed(std::span(bytes).first(cut), sim::SimTime{}, events);
    framer.feed(std::span(bytes).subspan(cut), sim::SimTime{}, events);
    INFO("cut at " << cut << ": " << test::summary(events));
    CHECK(test::summary(events) == "frame(id=1)");
  }
}

TEST_CASE("Status packets are stuffed like instructions", "[wire][stuffing]") {
  const wire::StatusPacket status{Protocol::V2, 3, 0x00, {0xFF, 0xFF, 0xFD, 0x10}};
  const Bytes bytes = wire::encode_status(status);
  CHECK(length_field(bytes) == 1 + 1 + 4 + 1 + 2);  // 0x55, error, params, stuffing, CRC
  const auto decoded = wire::decode_status(test::frame_one(Protocol::V2, bytes));
  REQUIRE(std::holds_alternative<wire::StatusPacket>(decoded));
  CHECK(std::get<wire::StatusPacket>(decoded) == status);
}

TEST_CASE("A Fast Sync Read reply whose data holds FF FF FD is sent and decoded unstuffed",
          "[wire][stuffing]") {
  const wire::FastReply reply{
      {{0x00, 3, {0xFF, 0xFF, 0xFD, 0xFD}}, {0x80, 4, {0xFF, 0xFF, 0xFD, 0x00}}}};
  const Bytes bytes = wire::encode_fast_reply(reply);
  // Not stuffed: LENGTH = 0x55 + two blocks of (error, ID, 4 data bytes, CRC).
  CHECK(length_field(bytes) == 1 + 2 * (2 + 4 + 2));
  CHECK(bytes.size() == 7 + length_field(bytes));
  const std::vector<std::uint16_t> lengths = {4, 4};
  const auto decoded = wire::decode_fast_reply(test::frame_one(Protocol::V2, bytes), lengths);
  REQUIRE(std::holds_alternative<wire::FastReply>(decoded));
  CHECK(std::get<wire::FastReply>(decoded) == reply);
}

TEST_CASE("A Fast reply with a wrong embedded CRC is refused naming the block",
          "[wire][stuffing]") {
  const wire::FastReply reply{{{0x00, 3, {0x01}}, {0x00, 4, {0x02}}}};
  Bytes bytes = wire::encode_fast_reply(reply);
  // Corrupt the first block's embedded CRC and fix the packet CRC so that the framer accepts it.
  bytes[11] ^= 0xFF;
  const std::uint16_t crc = wire::crc16(std::span(bytes).first(bytes.size() - 2));
  bytes[bytes.size() - 2] = static_cast<std::uint8_t>(crc & 0xFF);
  bytes[bytes.size() - 1] = static_cast<std::uint8_t>(crc >> 8);
  const std::vector<std::uint16_t> lengths = {1, 1};
  const auto decoded = wire::decode_fast_reply(test::frame_one(Protocol::V2, bytes), lengths);
  REQUIRE(std::holds_alternative<wire::DecodeError>(decoded));
  CHECK(std::get<wire::DecodeError>(decoded).reason == "fast reply block 1 (ID 3) has a wrong CRC");
}

TEST_CASE("Unstuffing starts at the instruction byte, where the sender's stuffing starts",
          "[wire][stuffing]") {
  // Found by fuzz_wire_v2: instruction 0xFF followed by FF FD forms FF FF FD across the
  // instruction byte. The sender stuffs it (FF FF FD FD), so the receiver must unstuff there too.
  const wire::InstructionPacket packet{Protocol::V2, 1,
                                       wire::UnknownInstruction{0xFF, {0xFF, 0xFD}}};
  const Bytes bytes = wire::encode_instruction(packet);
  CHECK(bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x06, 0x00, 0xFF, 0xFF, 0xFD, 0xFD, 0xF8, 0xD3});
  const auto decoded = wire::decode_instruction(test::frame_one(Protocol::V2, bytes));
  REQUIRE(std::holds_alternative<wire::InstructionPacket>(decoded));
  CHECK(std::get<wire::InstructionPacket>(decoded) == packet);
}

TEST_CASE("A 2.0 status packet from the broadcast ID is refused: only Fast replies come from there",
          "[wire][stuffing]") {
  CHECK_THROWS_AS(wire::encode_status({Protocol::V2, 0xFE, 0x00, {}}), std::invalid_argument);
  CHECK_NOTHROW(wire::encode_status({Protocol::V1, 0xFE, 0x00, {}}));
}
