// Bus behaviours that fuzz_bus (tests/fuzz/) found wrong, each reproduced with the packet the
// fuzzer's input boiled down to.
#include <catch2/catch.hpp>

#include "bus_rig.hpp"
#include "wire/modbus_codec.hpp"

using namespace dxlemu;
using test::BusRig;
using test::kBroadcast;
using wire::Protocol;

TEST_CASE("A Fast read whose reply would not fit a 2.0 LENGTH goes unanswered", "[bus][fuzz]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 2);
  // One block of 65535 data bytes (a failed read is zero-filled to the requested length) or two
  // blocks that add up to more than 65535: LENGTH cannot announce the reply. Encoding it threw
  // std::invalid_argument out of Bus::receive, which ended the daemon.
  SECTION("Fast Sync Read") {
    CHECK_NOTHROW(rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{0, 0xFFFF, {1}}}}));
  }
  SECTION("Fast Bulk Read") {
    CHECK_NOTHROW(rig.send(
        {Protocol::V2, kBroadcast, wire::FastBulkRead{{{{1, 132, 0x8000}, {2, 132, 0x7FF0}}}}}));
  }
  rig.run();
  CHECK(rig.link.deliveries().empty());
  // The largest Fast read that fits is still answered.
  // (It takes over 11 s to cross the line at 57600 bps.)
  rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{0, 0xFFFF - 5, {1}}}});
  rig.run(std::chrono::seconds(20));
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes.size() == 7 + 0xFFFF);
}

TEST_CASE("An empty write from the client leaves the replies still due in place", "[bus][fuzz]") {
  BusRig rig;
  std::uint32_t bps = BusRig::kBaud;
  SECTION("FEETECH") {
    rig.add("feetech/sts3215", 1);
    bps = 1000000;  // the STS3215's factory rate
    rig.send({Protocol::Feetech, 1, wire::Ping{}}, bps);
  }
  SECTION("Protocol 2.0") {
    rig.add("xm430-w350", 1);
    rig.send({Protocol::V2, 1, wire::Ping{}}, bps);
  }
  // fuzz_bus_feetech fed the end of its input as one more receive() of no bytes while the status
  // was due: it was counted as a collision and the status dropped.
  rig.bus.receive({}, rig.scheduler.now(), bps);
  rig.run();
  CHECK(rig.bus.stats().collisions == 0);
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("A FEETECH position calibration the Position offset cannot reach changes nothing",
          "[bus][fuzz][feetech]") {
  constexpr std::uint32_t kMbps = 1000000;  // the FEETECH models' factory rate
  BusRig rig;
  const std::string model =
      GENERATE(std::string("feetech/hls3625m"), std::string("feetech/sts3215"));
  model::Servo& servo = rig.add(model, 1);
  // The shaft is at 2048. Reading 0xFF07 there needs an offset of 2048 - 65287, far outside
  // -4095 ~ 4095 (HLS) or -2047 ~ 2047 (STS): fuzz_bus_feetech found Position offset clamped to
  // -32767 instead, a value no write could set.
  rig.send({Protocol::Feetech, 1, wire::PositionCalibration{0xFF07}}, kMbps);
  rig.run();
  CHECK(servo.table().get("position_offset") == 0);
  CHECK(servo.table().get("present_position") == 2048);
  // Refused with the range bit, which FEETECH models leave unset: error byte 0, no data.
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes ==
        std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  // A reachable value still calibrates.
  rig.send({Protocol::Feetech, 1, wire::PositionCalibration{1024}}, kMbps);
  rig.run();
  CHECK(servo.table().get("present_position") == 1024);
}

TEST_CASE("A 2.0 status stands when the Modbus servos reject the same bytes at the silence",
          "[bus][fuzz][modbus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  model::Servo& modbus = rig.add("ph54-200-s500-r", 2);
  modbus.table().set("protocol_type", wire::traits(Protocol::Modbus).type_value);
  modbus.commit_deferred();
  REQUIRE(modbus.protocol() == Protocol::Modbus);
  // The Modbus servo's framer takes the Ping's bytes for a frame with a bad CRC once t3.5 has
  // passed (1,750 us), before the status (Return Delay Time 500 us, then 14 bytes at 57600 bps)
  // is out: that rejection cancelled the status as if new bytes had come (found by
  // fuzz_bus_modbus, a servo switched to 2.0 among servos speaking Modbus).
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes).rfind("id=1 error=0x00 params=", 0) == 0);
  CHECK(rig.bus.stats().collisions == 0);
  CHECK(rig.bus.stats().bad_checks == 1);
}

TEST_CASE("A servo whose ID is over 247 is reached over Modbus by broadcast alone",
          "[bus][fuzz][modbus]") {
  BusRig rig;
  model::Servo& servo = rig.add("ph54-200-s500-r", 1);
  // ID 250, written over 2.0, then Protocol Type 10 (found by fuzz_bus_modbus: the servo
  // answered Modbus requests to address 250, which docs/modbus.md "Addresses" rules out).
  servo.table().set("id", 250);
  servo.table().set("protocol_type", wire::traits(Protocol::Modbus).type_value);
  servo.commit_deferred();
  REQUIRE(servo.protocol() == Protocol::Modbus);
  REQUIRE(servo.id() == 250);
  rig.bus.receive(
      wire::encode_modbus_frame(250, 0x03, std::vector<std::uint8_t>{0x00, 0x00, 0x00, 0x01}),
      rig.scheduler.now(), BusRig::kBaud);
  rig.bus.receive(
      wire::encode_modbus_frame(250, 0x06, std::vector<std::uint8_t>{0x01, 0x00, 0x00, 0x01}),
      rig.scheduler.now() + std::chrono::milliseconds(100), BusRig::kBaud);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(servo.table().get("torque_enable") == 0);
  // A broadcast write reaches it.
  rig.bus.receive(
      wire::encode_modbus_frame(0, 0x06, std::vector<std::uint8_t>{0x01, 0x00, 0x00, 0x01}),
      rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(servo.table().get("torque_enable") == 1);
}
