// The FEETECH framer: the Protocol 1.0 frame (FF FF, one-byte LENGTH, checksum), IDs 0 to 253 and
// the broadcast ID, no 2.0 header to step over, and 1.0's inter-byte timeout.
#include <catch2/catch.hpp>

#include "framer_events.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using sim::SimTime;
using wire::Framer;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

using test::concat;

constexpr auto kFeetech = Protocol::Feetech;

std::vector<wire::FramerEvent> frame_all(const Bytes& stream) {
  Framer framer(kFeetech);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  framer.expire(SimTime{} + 1s, events);
  return events;
}

std::string summary(const Bytes& stream) {
  return test::summary(frame_all(stream));
}

const Bytes kPing1 = {0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB};  // protocol-ft-scs.md 4.1 Example 1

}  // namespace

TEST_CASE("The FEETECH frame format is Protocol 1.0's", "[wire][feetech][framer]") {
  const auto ft = wire::FrameFormat::for_protocol(kFeetech);
  const auto v1 = wire::FrameFormat::for_protocol(Protocol::V1);
  CHECK(ft.protocol == kFeetech);
  CHECK(ft.header == Bytes{0xFF, 0xFF});
  CHECK(ft.length_field_bytes == 1);
  CHECK(ft.min_length == 2);
  CHECK(ft.max_length == 255);
  CHECK(ft.check_bytes == 1);
  CHECK(ft.inter_byte_timeout == v1.inter_byte_timeout);
  CHECK(ft.inter_byte_timeout == 100ms);
}

TEST_CASE("A FEETECH packet with a wrong checksum is rejected, and the next one still framed",
          "[wire][feetech][framer]") {
  Bytes broken = kPing1;
  broken.back() ^= 0x01U;
  const auto events = frame_all(concat({broken, kPing1}));
  CHECK(test::summary(events) == "bad_check(id=1) frame(id=1)");
  const auto errors = test::errors_of(events);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].protocol == kFeetech);
  CHECK(errors[0].instruction == std::uint8_t{0x01});
  CHECK(errors[0].raw == broken);
}

TEST_CASE("FEETECH frames IDs 0 to 253 and the broadcast ID, and FF is no ID",
          "[wire][feetech][framer]") {
  for (const unsigned id : {0U, 1U, 252U, 253U, 254U}) {
    INFO("id " << id);
    const auto ping =
        wire::encode_instruction({kFeetech, static_cast<std::uint8_t>(id), wire::Ping{}});
    const auto frames = test::frames_of(frame_all(ping));
    REQUIRE(frames.size() == 1);
    CHECK(frames[0].id == id);
    CHECK(frames[0].protocol == kFeetech);
  }
  // FF FF FF 01 ...: the first FF is garbage, the frame starts at the last FF FF.
  CHECK(summary(concat({{0xFF}, kPing1})) == "garbage(1) frame(id=1)");
}

TEST_CASE("FF FF FD is a FEETECH packet to ID 253, not a 2.0 header", "[wire][feetech][framer]") {
  // A status from ID 253: FF FF FD 02 00 checksum.
  const Bytes status = wire::encode_status({kFeetech, 0xFD, 0, {}});
  CHECK(status == Bytes{0xFF, 0xFF, 0xFD, 0x02, 0x00, 0x00});
  const auto frames = test::frames_of(frame_all(status));
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].id == 0xFD);
  // The 2.0 header FF FF FD 00 is a packet to ID 253 whose LENGTH 0 is impossible: reported, and
  // the packet right after it is still found. (The 1.0 framer skips it as 2.0 traffic.)
  CHECK(summary(concat({{0xFF, 0xFF, 0xFD, 0x00}, kPing1})) ==
        "impossible_length(id=253) frame(id=1)");
}

TEST_CASE("FEETECH LENGTH must be 2 to 255", "[wire][feetech][framer]") {
  CHECK(summary(concat({{0xFF, 0xFF, 0x01, 0x00}, kPing1})) ==
        "impossible_length(id=1) frame(id=1)");
  CHECK(summary(concat({{0xFF, 0xFF, 0x01, 0x01}, kPing1})) ==
        "impossible_length(id=1) frame(id=1)");
  // The longest packet: LENGTH 255, a write of 252 data bytes.
  const Bytes longest =
      wire::encode_instruction({kFeetech, 1, wire::Write{0x00, Bytes(252, 0x11)}});
  REQUIRE(longest[3] == 0xFF);
  const auto frames = test::frames_of(frame_all(longest));
  REQUIRE(frames.size() == 1);
  const auto decoded = wire::decode_instruction(frames[0]);
  REQUIRE(std::holds_alternative<wire::InstructionPacket>(decoded));
  CHECK(std::get<wire::Write>(std::get<wire::InstructionPacket>(decoded).instruction).data.size() ==
        252);
}

TEST_CASE("A partial FEETECH packet is dropped after 1.0's inter-byte timeout",
          "[wire][feetech][framer]") {
  Framer framer(kFeetech);
  std::vector<wire::FramerEvent> events;
  const std::span<const std::uint8_t> ping(kPing1);
  // A gap of exactly 100 ms still continues the packet.
  framer.feed(ping.first(3), SimTime{}, events);
  framer.feed(ping.subspan(3), SimTime{} + 100ms, events);
  CHECK(test::summary(events) == "frame(id=1)");
  events.clear();
  // One nanosecond more drops the partial packet; the bytes after it are resynchronised on.
  framer.feed(ping.first(3), SimTime{} + 1s, events);
  REQUIRE(framer.deadline() == SimTime{} + 1s + 100ms + sim::SimDuration{1});
  framer.feed(kPing1, SimTime{} + 1s + 100ms + sim::SimDuration{1}, events);
  CHECK(test::summary(events) == "truncated(3) frame(id=1)");
}
