// What FEETECH servos do with the packets they refuse, where their error byte (the servo status)
// has no bit to say "no": silence to a bad checksum, an unknown or malformed instruction and a
// read outside the table, an acknowledgement with error 0 to a refused write; a model file's
// `refusal_bits` changing that; and DYNAMIXEL untouched (docs/feetech.md "Refusals").
#include <catch2/catch.hpp>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "feetech_rig.hpp"
#include "model/spec/model_loader.hpp"

namespace dxlemu {
namespace {

using namespace std::chrono_literals;
using namespace test::feetech;
using test::BusRig;
using test::kBroadcast;
using test::line;
using wire::Protocol;

// STS3215's table ends with Acceleration multiplier (86); SCS0009's with Acceleration (83).
constexpr std::uint8_t kStsTableSize = 87;
constexpr std::uint8_t kScsTableSize = 84;
// STS3215 Acceleration limit: a read-only factory parameter LeRobot writes 254 to.
constexpr std::uint8_t kStsAccelerationLimit = 85;

/// The bytes of `packet` with its checksum broken.
std::vector<std::uint8_t> with_bad_checksum(const wire::InstructionPacket& packet) {
  std::vector<std::uint8_t> bytes = wire::encode_instruction(packet);
  bytes.back() ^= 0x01;
  return bytes;
}

const std::string kStsPath = std::string(DXLEMU_MODELS_DIR) + "/feetech/sts3215.json";

/// The shipped STS3215 model file as JSON.
nlohmann::json sts3215_document() {
  std::ifstream in(kStsPath);
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

/// The STS3215 model with `refusal_bits` set to `refusals`, loaded as from its file.
std::shared_ptr<const model::ModelSpec> sts3215_with(const nlohmann::json& refusals) {
  nlohmann::json document = sts3215_document();
  document["refusal_bits"] = refusals;
  return std::make_shared<const model::ModelSpec>(model::model_from_json(document, kStsPath));
}

/// What the loader says of the STS3215 file with `refusal_bits` set to `refusals` (empty when
/// it loads).
std::string refusal_bits_error(const nlohmann::json& refusals) {
  try {
    sts3215_with(refusals);
  } catch (const model::ModelError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("A FEETECH servo stays silent to a packet with a bad checksum", "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  for (const wire::Instruction& instruction :
       {wire::Instruction{wire::Ping{}}, wire::Instruction{wire::Read{56, 2}},
        wire::Instruction{wire::Write{42, {0x00, 0x08}}}}) {
    rig.bus.receive(with_bad_checksum({Protocol::Feetech, 1, instruction}), rig.scheduler.now(),
                    kRate);
    rig.run();
  }
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.stats().bad_checks == 3);
  CHECK(rig.bus.servos()[0]->table().get("goal_position") == 2048);  // the write did not land
  // The servo is none the worse: the next good packet is answered on time.
  const sim::SimTime sent_at = rig.scheduler.now();
  const std::size_t sent = send(rig, 1, wire::Ping{});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes ==
        std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  CHECK(rig.link.deliveries()[0].at == sent_at + line(sent, kRate) + kProcessing + line(6, kRate));
}

TEST_CASE("A FEETECH servo stays silent to an instruction it does not know or cannot make out",
          "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  rig.add("feetech/scs0009", 2);
  SECTION("an unknown instruction byte, DYNAMIXEL's Bulk Read code among them") {
    send(rig, 1, wire::UnknownInstruction{0x92, {}});
    rig.run();
    send(rig, 1, wire::UnknownInstruction{0x30, {0x01, 0x02}});
    rig.run();
  }
  SECTION("a malformed instruction: a READ with one parameter, a PING with one") {
    rig.bus.receive(std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x03, 0x02, 0x38, 0xC1},
                    rig.scheduler.now(), kRate);
    rig.run();
    rig.bus.receive(std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x03, 0x01, 0x00, 0xFA},
                    rig.scheduler.now(), kRate);
    rig.run();
    CHECK(rig.bus.stats().decode_errors == 2);
  }
  SECTION("position calibration on SCS, whose firmware has no such instruction") {
    send(rig, 2, wire::PositionCalibration{});
    rig.run();
  }
  CHECK(rig.link.deliveries().empty());
}

TEST_CASE("A FEETECH READ outside the table gets no reply, in whole or in part", "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  send(rig, 1, wire::Read{90, 2});  // past the end
  rig.run();
  send(rig, 1, wire::Read{kStsTableSize - 1, 2});  // its last byte and one past it
  rig.run();
  send(rig, 1, wire::Read{0, 255});  // more than the whole table
  rig.run();
  CHECK(rig.link.deliveries().empty());
  // Up to the table's last byte it is answered, undefined addresses (71 ~ 79 on STS) included.
  send(rig, 1, wire::Read{kStsTableSize - 1, 1});
  rig.run();
  send(rig, 1, wire::Read{70, 17});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(status(d[0]).rfind("id=1 error=0x00 params=", 0) == 0);
  CHECK(d[0].bytes.size() == 7);
  CHECK(d[1].bytes.size() == 6 + 17);
}

TEST_CASE("A FEETECH READ outside the table is silent at Response level 0 too", "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1).table().set("response_status_level", 0);
  send(rig, 1, wire::Read{kStsTableSize, 1});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  send(rig, 1, wire::Read{56, 2});
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("A SYNC READ part outside a servo's table silences it and stops the chain there",
          "[bus][feetech][timing]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  rig.add("feetech/scs0009", 2);
  rig.add("feetech/sts3215", 3);
  SECTION("within the STS3215 table, past the SCS0009's") {
    const std::size_t sent = send(rig, kBroadcast, wire::SyncRead{kScsTableSize, 3, {1, 2, 3}});
    rig.run(2s);
    // ID 1 answers; ID 2 has nothing to send, and ID 3 waits for its status in vain.
    const auto& d = rig.link.deliveries();
    REQUIRE(d.size() == 1);
    CHECK(status(d[0]).rfind("id=1 error=0x00 params=", 0) == 0);
    CHECK(d[0].at == sim::SimTime{} + line(sent, kRate) + kProcessing + line(6 + 3, kRate));
  }
  SECTION("the silent servo listed last: the ones before it answer") {
    send(rig, kBroadcast, wire::SyncRead{kScsTableSize, 3, {3, 1, 2}});
    rig.run(2s);
    const auto& d = rig.link.deliveries();
    REQUIRE(d.size() == 2);
    CHECK(status(d[0]).rfind("id=3 ", 0) == 0);
    CHECK(status(d[1]).rfind("id=1 ", 0) == 0);
  }
  SECTION("past every table: nobody answers") {
    send(rig, kBroadcast, wire::SyncRead{kStsTableSize - 1, 2, {1, 2, 3}});
    rig.run(2s);
    CHECK(rig.link.deliveries().empty());
  }
}

TEST_CASE("Where FEETECH servos share an ID, one whose table is too short drops out silently",
          "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  rig.add("feetech/scs0009", 1);
  rig.add("feetech/sts3215", 2);
  send(rig, kBroadcast, wire::SyncRead{kScsTableSize, 1, {1, 2}});
  rig.run(2s);
  // The STS3215 at ID 1 answers alone (no collision), and ID 2 follows it.
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(status(d[0]).rfind("id=1 error=0x00 params=", 0) == 0);
  CHECK(status(d[1]).rfind("id=2 error=0x00 params=", 0) == 0);
  CHECK(rig.bus.stats().id_conflicts == 0);
}

TEST_CASE("A FEETECH write the table refuses is acknowledged with error 0 and changes nothing",
          "[bus][feetech]") {
  BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  const std::int64_t before = servo.table().get("acceleration_limit");
  SECTION("a read-only factory parameter (LeRobot's write of 254 to 85)") {
    send(rig, 1, wire::Write{kStsAccelerationLimit, {254}});
    rig.run();
    REQUIRE(rig.link.deliveries().size() == 1);
    CHECK(rig.link.deliveries()[0].bytes ==
          std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
    CHECK(servo.table().get("acceleration_limit") == before);
  }
  SECTION("a value out of range, and past the table") {
    send(rig, 1, wire::Write{26, {17}});  // Positive deadband 0 ~ 16
    rig.run();
    send(rig, 1, wire::Write{kStsTableSize, {1}});
    rig.run();
    const auto& d = rig.link.deliveries();
    REQUIRE(d.size() == 2);
    CHECK(status(d[0]) == "id=1 error=0x00");
    CHECK(status(d[1]) == "id=1 error=0x00");
    CHECK(servo.table().get("positive_deadband") == 1);
  }
}

TEST_CASE("FEETECH ACTION with nothing registered is answered as any ACTION", "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  send(rig, 1, wire::Action{});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(status(rig.link.deliveries()[0]) == "id=1 error=0x00");
}

TEST_CASE("A model file's refusal_bits give a refusal a bit instead of silence, or silence",
          "[bus][feetech][loader]") {
  BusRig rig;
  const auto spec = sts3215_with(
      {{"checksum", 0x10}, {"instruction", 0x40}, {"read", 0x80}, {"range", "silent"}});
  CHECK(spec->refusals() == model::Refusals{.checksum = {.silent = false, .bit = 0x10},
                                            .instruction = {.silent = false, .bit = 0x40},
                                            .read = {.silent = false, .bit = 0x80},
                                            .range = wire::kSilentRefusal});
  rig.bus.add_servo(std::make_unique<model::Servo>(spec, 1));
  rig.add("feetech/sts3215", 2);
  rig.bus.receive(with_bad_checksum({Protocol::Feetech, 1, wire::Ping{}}), rig.scheduler.now(),
                  kRate);
  rig.run();
  send(rig, 1, wire::UnknownInstruction{0x92, {}});
  rig.run();
  send(rig, 1, wire::Read{kStsTableSize, 2});
  rig.run();
  send(rig, 1, wire::Write{kStsAccelerationLimit, {254}});  // silent now
  rig.run();
  // A SYNC READ part outside the table answered with the bit: the chain goes on to ID 2, whose
  // model keeps its family's silence.
  send(rig, kBroadcast, wire::SyncRead{kStsTableSize - 1, 2, {1, 2}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 4);
  CHECK(d[0].bytes == std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x10, 0xEC});
  CHECK(status(d[1]) == "id=1 error=0x40");
  CHECK(status(d[2]) == "id=1 error=0x80");  // no data
  CHECK(status(d[3]) == "id=1 error=0x80");
}

TEST_CASE("A model file's refusal_bits keep the family's answers it does not name",
          "[model][loader][feetech]") {
  const auto spec = sts3215_with({{"read", 0}});
  CHECK(spec->refusals().read == wire::RefusalAnswer{});
  CHECK(spec->refusals().checksum == wire::kSilentRefusal);
  CHECK(spec->refusals().instruction == wire::kSilentRefusal);
  CHECK(spec->refusals().range == wire::RefusalAnswer{});
  CHECK(test::shipped_model("feetech/sts3215")->refusals() ==
        model::Refusals{.checksum = wire::kSilentRefusal,
                        .instruction = wire::kSilentRefusal,
                        .read = wire::kSilentRefusal,
                        .range = {}});
}

TEST_CASE("Bad refusal_bits values are refused naming the file, the JSON pointer and the reason",
          "[model][loader][feetech]") {
  const std::string file = kStsPath + ": ";
  CHECK(refusal_bits_error({{"read", "silence"}}) ==
        file + "/refusal_bits/read: must be \"silent\" or a status bit, got \"silence\"");
  CHECK(refusal_bits_error({{"checksum", true}}) ==
        file + "/refusal_bits/checksum: must be \"silent\" or a status bit (an integer 0 ~ 255)");
  CHECK(refusal_bits_error({{"instruction", 1.5}}) ==
        file +
            "/refusal_bits/instruction: must be \"silent\" or a status bit (an integer 0 ~ 255)");
  CHECK(refusal_bits_error({{"range", nullptr}}) ==
        file + "/refusal_bits/range: must be \"silent\" or a status bit (an integer 0 ~ 255)");
  CHECK(refusal_bits_error({{"range", 256}}) ==
        file + "/refusal_bits/range: must be between 0 and 255, got 256");
  CHECK(refusal_bits_error({{"read", 0x20}}) ==
        file +
            "/refusal_bits/read: uses a bit FEETECH defines for a hardware error (1, 2, 4, 8, "
            "32 are taken)");
  CHECK(refusal_bits_error({{"write", "silent"}}) == file + "/refusal_bits/write: unknown field");
  CHECK(refusal_bits_error("silent") == file + "/refusal_bits: must be an object");
  CHECK(refusal_bits_error({{"read", "silent"}}).empty());
}

TEST_CASE("refusal_bits is refused on a DYNAMIXEL model, silent or not", "[model][loader]") {
  const std::string path = std::string(DXLEMU_MODELS_DIR) + "/ax-12a.json";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json document = nlohmann::json::parse(text.str());
  document["refusal_bits"] = {{"checksum", "silent"}};
  CHECK_THROWS_WITH(model::model_from_json(document, path),
                    path + ": /refusal_bits: is a setting of FEETECH models only");
}

TEST_CASE("DYNAMIXEL Protocol 1.0 still answers every refusal with its error bit", "[bus]") {
  constexpr std::uint32_t kAxRate = 1'000'000;  // AX-12A's factory rate
  BusRig rig;
  rig.add("ax-12a", 1);
  auto bad = wire::encode_instruction({Protocol::V1, 1, wire::Read{36, 2}});
  bad.back() ^= 0x01;
  rig.bus.receive(bad, rig.scheduler.now(), kAxRate);
  rig.run();
  rig.send({Protocol::V1, 1, wire::UnknownInstruction{0x30, {}}}, kAxRate);
  rig.run();
  rig.send({Protocol::V1, 1, wire::Read{70, 4}}, kAxRate);  // past the table
  rig.run();
  rig.send({Protocol::V1, 1, wire::Action{}}, kAxRate);  // nothing registered
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 4);
  CHECK(d[0].bytes == std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x10, 0xEC});
  CHECK(test::status_text(d[1].bytes, Protocol::V1) == "id=1 error=0x40");
  CHECK(test::status_text(d[2].bytes, Protocol::V1) == "id=1 error=0x08");
  CHECK(test::status_text(d[3].bytes, Protocol::V1) == "id=1 error=0x40");
}

}  // namespace dxlemu
