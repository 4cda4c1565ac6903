// Every example frame of FEETECH's FT-SCS protocol page decodes to the fields the page states and
// re-encodes to the page's bytes; the frames survive any split, and garbage around them.
#include <catch2/catch.hpp>

#include "feetech_examples.hpp"
#include "framer_events.hpp"
#include "wire/describe.hpp"
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

// Frames one example delivered in a single chunk; exactly one frame and nothing else is expected.
Bytes all_examples() {
  Bytes out;
  for (const auto& e : test::feetech_examples()) {
    out.insert(out.end(), e.bytes.begin(), e.bytes.end());
  }
  return out;
}

}  // namespace

TEST_CASE("The FEETECH examples are the page's 36 distinct frames", "[wire][feetech][golden]") {
  const auto& examples = test::feetech_examples();
  std::size_t instructions = 0;
  for (std::size_t i = 0; i < examples.size(); ++i) {
    INFO(examples[i].section);
    CHECK((examples[i].kind == "instruction" || examples[i].kind == "status"));
    instructions += examples[i].kind == "instruction" ? 1 : 0;
    for (std::size_t j = 0; j < i; ++j) {
      CHECK(examples[j].bytes != examples[i].bytes);
    }
  }
  CHECK(examples.size() == 36);
  CHECK(instructions == 23);
}

TEST_CASE("FEETECH example instructions decode to the page's fields and re-encode byte for byte",
          "[wire][feetech][golden]") {
  for (const auto& e : test::feetech_examples()) {
    if (e.kind != "instruction") {
      continue;
    }
    INFO(e.section);
    const wire::Frame frame = test::frame_one(Protocol::Feetech, e.bytes);
    CHECK(frame.protocol == Protocol::Feetech);
    const auto decoded = wire::decode_instruction(frame);
    REQUIRE(std::holds_alternative<wire::InstructionPacket>(decoded));
    const auto& packet = std::get<wire::InstructionPacket>(decoded);
    CHECK(packet.protocol == Protocol::Feetech);
    CHECK(wire::describe(packet) == e.expect);
    CHECK(wire::encode_instruction(packet) == e.bytes);
  }
}

TEST_CASE("FEETECH example status frames decode to the page's fields and re-encode byte for byte",
          "[wire][feetech][golden]") {
  for (const auto& e : test::feetech_examples()) {
    if (e.kind != "status") {
      continue;
    }
    INFO(e.section);
    const auto decoded = wire::decode_status(test::frame_one(Protocol::Feetech, e.bytes));
    REQUIRE(std::holds_alternative<wire::StatusPacket>(decoded));
    const auto& status = std::get<wire::StatusPacket>(decoded);
    CHECK(status.protocol == Protocol::Feetech);
    CHECK(wire::describe(status) == e.expect);
    CHECK(wire::encode_status(status) == e.bytes);
  }
}

TEST_CASE("The FEETECH-only examples decode to their own instruction types",
          "[wire][feetech][golden]") {
  auto instruction = [](const Bytes& bytes) {
    return std::get<wire::InstructionPacket>(
               wire::decode_instruction(test::frame_one(Protocol::Feetech, bytes)))
        .instruction;
  };
  // 4.9 Example 11: "Set value: 00 04(1024)"; Example 10 has none (the middle position).
  const auto calibrate = instruction({0xFF, 0xFF, 0x01, 0x04, 0x0B, 0x00, 0x04, 0xEB});
  REQUIRE(std::holds_alternative<wire::PositionCalibration>(calibrate));
  CHECK(std::get<wire::PositionCalibration>(calibrate).position == std::uint16_t{1024});
  const auto middle = instruction({0xFF, 0xFF, 0x01, 0x02, 0x0B, 0xF1});
  REQUIRE(std::holds_alternative<wire::PositionCalibration>(middle));
  CHECK_FALSE(std::get<wire::PositionCalibration>(middle).position.has_value());
  CHECK(
      std::holds_alternative<wire::StatusReset>(instruction({0xFF, 0xFF, 0x01, 0x02, 0x0A, 0xF2})));
  CHECK(std::holds_alternative<wire::ParameterRecovery>(
      instruction({0xFF, 0xFF, 0x01, 0x02, 0x06, 0xF6})));
  CHECK(std::holds_alternative<wire::ParameterBackup>(
      instruction({0xFF, 0xFF, 0x01, 0x02, 0x09, 0xF3})));
  CHECK(std::holds_alternative<wire::Reboot>(instruction({0xFF, 0xFF, 0x01, 0x02, 0x08, 0xF4})));
  // 4.7 Example 8: the IDs in request order, one-byte address and length.
  const auto sync_read = instruction({0xFF, 0xFF, 0xFE, 0x06, 0x82, 0x38, 0x08, 0x01, 0x02, 0x36});
  REQUIRE(std::holds_alternative<wire::SyncRead>(sync_read));
  CHECK(std::get<wire::SyncRead>(sync_read) == wire::SyncRead{0x38, 8, {1, 2}});
}

TEST_CASE("The same bytes mean different instructions in Protocol 1.0 and FEETECH",
          "[wire][feetech][golden]") {
  // 4.10: FF FF 01 02 06 F6 is Parameter recovery to FEETECH, Factory Reset to a 1.0 servo.
  const Bytes recovery = {0xFF, 0xFF, 0x01, 0x02, 0x06, 0xF6};
  Framer v1(Protocol::V1);
  std::vector<wire::FramerEvent> events;
  v1.feed(recovery, SimTime{}, events);
  const auto frames = test::frames_of(events);
  REQUIRE(frames.size() == 1);
  const auto as_v1 = wire::decode_instruction(frames[0]);
  REQUIRE(std::holds_alternative<wire::InstructionPacket>(as_v1));
  CHECK(wire::describe(std::get<wire::InstructionPacket>(as_v1)) ==
        "id=1 factory_reset option=0xFF");
  const auto as_feetech = wire::decode_instruction(test::frame_one(Protocol::Feetech, recovery));
  REQUIRE(std::holds_alternative<wire::InstructionPacket>(as_feetech));
  CHECK(wire::describe(std::get<wire::InstructionPacket>(as_feetech)) == "id=1 parameter_recovery");
}

TEST_CASE("Every FEETECH example split at every byte boundary yields the same frame",
          "[wire][feetech][split]") {
  for (const auto& e : test::feetech_examples()) {
    const std::span<const std::uint8_t> bytes(e.bytes);
    for (std::size_t cut = 1; cut < bytes.size(); ++cut) {
      INFO(e.section << " cut at " << cut);
      Framer framer(Protocol::Feetech);
      std::vector<wire::FramerEvent> events;
      const SimTime t0{};
      const SimTime t1 = t0 + 1ms;
      framer.feed(bytes.first(cut), t0, events);
      CHECK(events.empty());
      CHECK(framer.buffered() == cut);
      framer.feed(bytes.subspan(cut), t1, events);
      REQUIRE(events.size() == 1);
      const auto frames = test::frames_of(events);
      REQUIRE(frames.size() == 1);
      CHECK(frames[0].raw == e.bytes);
      CHECK(frames[0].first_byte_at == t0);
      CHECK(frames[0].last_byte_at == t1);
    }
  }
}

TEST_CASE("All FEETECH examples back to back, in chunks of every size, come out in order",
          "[wire][feetech][split]") {
  const Bytes stream = all_examples();
  const auto& examples = test::feetech_examples();
  for (std::size_t chunk = 1; chunk <= 17; ++chunk) {
    INFO("chunk size " << chunk);
    Framer framer(Protocol::Feetech);
    std::vector<wire::FramerEvent> events;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      const std::size_t n = std::min(chunk, stream.size() - at);
      framer.feed(std::span(stream).subspan(at, n), SimTime{}, events);
    }
    CHECK(test::errors_of(events).empty());
    const auto frames = test::frames_of(events);
    REQUIRE(frames.size() == examples.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      CHECK(frames[i].raw == examples[i].bytes);
    }
  }
}

TEST_CASE("Garbage before, between and after the FEETECH examples is skipped and counted",
          "[wire][feetech][garbage]") {
  // Stray bytes, a lone FF and an FF FF FF run: none of them hides the packet after it.
  const std::vector<Bytes> junk = {{0x13, 0x37}, {0xFF}, {0x00, 0xFE}, {0xFF, 0xFF, 0xFF}};
  Bytes stream;
  std::size_t junk_bytes = 0;
  const auto& examples = test::feetech_examples();
  for (std::size_t i = 0; i < examples.size(); ++i) {
    const Bytes& j = junk[i % junk.size()];
    stream.insert(stream.end(), j.begin(), j.end());
    junk_bytes += j.size();
    stream.insert(stream.end(), examples[i].bytes.begin(), examples[i].bytes.end());
  }
  Framer framer(Protocol::Feetech);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  const auto frames = test::frames_of(events);
  INFO(test::summary(events));
  REQUIRE(frames.size() == examples.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    CHECK(frames[i].raw == examples[i].bytes);
  }
  std::size_t garbage = 0;
  for (const auto& e : test::errors_of(events)) {
    CHECK(e.kind == wire::FramingErrorKind::Garbage);
    garbage += e.bytes;
  }
  CHECK(garbage == junk_bytes);
}
