// Trace lines (docs/trace.md): one JSON object per packet each way, decoded.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "app/record/trace_record.hpp"
#include "wire/framer.hpp"
#include "wire/hex.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;

namespace {

wire::Frame frame_of(const std::vector<std::uint8_t>& bytes, wire::Protocol protocol,
                     sim::SimTime at) {
  wire::Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, at, events);
  REQUIRE(events.size() == 1);
  return std::get<wire::Frame>(events[0]);
}

}  // namespace

TEST_CASE("An instruction heard is traced with time, port, direction, bytes and decoded text",
          "[app][trace]") {
  const auto bytes = wire::encode_instruction({wire::Protocol::V2, 1, wire::Read{132, 4}});
  const auto at = sim::SimTime{} + 1500us;
  CHECK(app::heard_record("dxl0", frame_of(bytes, wire::Protocol::V2, at)) ==
        R"({"t":0.0015,"port":"dxl0","dir":"in","protocol":2,"id":1,)"
        R"("hex":"FF FF FD 00 01 07 00 02 84 00 04 00 1D 15",)"
        R"("packet":"id=1 read address=132 length=4"})");
}

TEST_CASE("A frame that does not decode and a framing failure are traced as problems",
          "[app][trace]") {
  // A 1.0 Read with one parameter byte instead of two.
  const std::vector<std::uint8_t> short_read = {0xFF, 0xFF, 0x01, 0x03, 0x02, 0x2B, 0xCE};
  const auto record = nlohmann::json::parse(
      app::heard_record("dxl0", frame_of(short_read, wire::Protocol::V1, sim::SimTime{})));
  CHECK(record["protocol"] == 1);
  CHECK(record.contains("problem"));
  CHECK(!record.contains("packet"));

  const wire::FramingError bad{
      wire::FramingErrorKind::BadCheck, wire::Protocol::V2, 10, 3, 1, sim::SimTime{} + 2s};
  CHECK(
      app::heard_record("arm", bad) ==
      R"({"t":2.0,"port":"arm","dir":"in","protocol":2,"problem":"bad_check","bytes":10,"id":3})");
}

TEST_CASE("A reply sent is traced decoded, colliding bytes are traced as a problem",
          "[app][trace]") {
  const auto status = wire::encode_status({wire::Protocol::V2, 1, 0, {0xFC, 0x03, 0x2D}});
  const auto parsed = [](const std::string& line) { return nlohmann::json::parse(line); };
  const auto record =
      parsed(app::sent_record("dxl0", status, sim::SimTime{} + 3ms, wire::Protocol::V2));
  CHECK(record["dir"] == "out");
  CHECK(record["packet"] == "id=1 error=0x00 params=FC 03 2D");
  auto garbled = status;
  garbled[9] &= 0x0F;
  const auto collided =
      parsed(app::sent_record("dxl0", garbled, sim::SimTime{}, wire::Protocol::V2));
  CHECK(collided["problem"] == "not a complete packet (colliding or cut-short replies)");

  const auto v1 = wire::encode_status({wire::Protocol::V1, 5, 0x20, {}});
  CHECK(parsed(app::sent_record("dxl0", v1, sim::SimTime{}, wire::Protocol::V1))["packet"] ==
        "id=5 error=0x20");
  CHECK_FALSE(record.contains("late_us"));  // manual timing: nothing measures it
}

TEST_CASE("A reply's record says how late it went out when that is measured", "[app][trace]") {
  const auto status = wire::encode_status({wire::Protocol::V2, 1, 0, {}});
  CHECK(app::sent_record("dxl0", status, sim::SimTime{} + 3ms, wire::Protocol::V2,
                         std::chrono::microseconds(1250)) ==
        R"({"t":0.003,"port":"dxl0","dir":"out","protocol":2,"hex":")" + wire::to_hex(status) +
            R"(","packet":"id=1 error=0x00","late_us":1250.0})");
}

TEST_CASE("FEETECH packets are traced with the protocol named, both ways", "[app][trace]") {
  // FEETECH's Sync Read example (protocol-ft-scs.md 4.7) and a status of ID 1.
  const std::vector<std::uint8_t> sync_read = {0xFF, 0xFF, 0xFE, 0x06, 0x82,
                                               0x38, 0x08, 0x01, 0x02, 0x36};
  const auto heard = nlohmann::json::parse(
      app::heard_record("arm", frame_of(sync_read, wire::Protocol::Feetech, sim::SimTime{})));
  CHECK(heard["protocol"] == "feetech");
  CHECK(heard["packet"] == "id=254 sync_read address=56 length=8 ids=1 2");
  const auto status = wire::encode_status({wire::Protocol::Feetech, 1, 0x04, {0x00, 0x08}});
  const auto sent = nlohmann::json::parse(
      app::sent_record("arm", status, sim::SimTime{}, wire::Protocol::Feetech));
  CHECK(sent["protocol"] == "feetech");
  CHECK(sent["dir"] == "out");
}
