// Every example packet of protocol1.md and protocol2.md decodes to the documented fields and
// re-encodes to the same bytes (tests/data/golden_packets.txt).
#include <catch2/catch.hpp>

#include "framer_events.hpp"
#include "golden_file.hpp"
#include "wire/describe.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using wire::Framer;

namespace {

// Frames one packet delivered in a single chunk; exactly one frame and nothing else is expected.
wire::Frame frame_one(const test::GoldenPacket& p) {
  INFO(p.name);
  return test::frame_one(p.protocol, p.bytes);
}

}  // namespace

TEST_CASE("The golden file holds every example packet of both protocol pages", "[wire][golden]") {
  const auto packets = test::load_golden_packets();
  std::size_t v1 = 0;
  std::size_t v2 = 0;
  for (const auto& p : packets) {
    (p.protocol == wire::Protocol::V1 ? v1 : v2)++;
  }
  // 18 examples on protocol1.md, 35 on protocol2.md, plus the CRC page's worked example.
  CHECK(v1 == 18);
  CHECK(v2 == 36);
}

TEST_CASE(
    "Golden instruction packets decode to the documented fields and re-encode to the same bytes",
    "[wire][golden]") {
  for (const auto& p : test::load_golden_packets()) {
    if (p.kind != "instruction") {
      continue;
    }
    INFO(p.name << " (" << p.source << ")");
    const auto decoded = wire::decode_instruction(frame_one(p));
    REQUIRE(std::holds_alternative<wire::InstructionPacket>(decoded));
    const auto& packet = std::get<wire::InstructionPacket>(decoded);
    CHECK(wire::describe(packet) == p.expect);
    CHECK(wire::encode_instruction(packet) == p.bytes);
  }
}

TEST_CASE("Golden status packets decode to the documented fields and re-encode to the same bytes",
          "[wire][golden]") {
  for (const auto& p : test::load_golden_packets()) {
    if (p.kind != "status") {
      continue;
    }
    INFO(p.name << " (" << p.source << ")");
    const auto decoded = wire::decode_status(frame_one(p));
    REQUIRE(std::holds_alternative<wire::StatusPacket>(decoded));
    const auto& status = std::get<wire::StatusPacket>(decoded);
    CHECK(wire::describe(status) == p.expect);
    CHECK(wire::encode_status(status) == p.bytes);
  }
}

TEST_CASE("Golden Fast Sync/Bulk Read replies decode block by block and re-encode unstuffed",
          "[wire][golden]") {
  std::size_t seen = 0;
  for (const auto& p : test::load_golden_packets()) {
    if (p.kind != "fast_reply") {
      continue;
    }
    ++seen;
    INFO(p.name << " (" << p.source << ")");
    const auto decoded = wire::decode_fast_reply(frame_one(p), p.lengths);
    REQUIRE(std::holds_alternative<wire::FastReply>(decoded));
    const auto& reply = std::get<wire::FastReply>(decoded);
    CHECK(wire::describe(reply) == p.expect);
    CHECK(wire::encode_fast_reply(reply) == p.bytes);
  }
  CHECK(seen == 2);
}

TEST_CASE("Examples whose CRC the page misprints are rejected as printed and accepted corrected",
          "[wire][golden]") {
  // protocol2-crc.md lists two misprinted CRCs: the Control Table Backup restore packet and the
  // Fast Bulk Read instruction packet. The golden file holds the corrected bytes in `bytes`.
  std::size_t misprints = 0;
  for (const auto& p : test::load_golden_packets()) {
    if (!p.printed) {
      continue;
    }
    ++misprints;
    INFO(p.name);
    Framer framer(p.protocol);
    std::vector<wire::FramerEvent> events;
    framer.feed(*p.printed, sim::SimTime{}, events);
    REQUIRE(!events.empty());
    const auto errors = test::errors_of(events);
    REQUIRE(!errors.empty());
    CHECK(errors.front().kind == wire::FramingErrorKind::BadCheck);
    CHECK(test::frames_of(events).empty());
    frame_one(p);
  }
  CHECK(misprints == 2);
}
