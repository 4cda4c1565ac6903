// FEETECH servos on a bus: framing, group instructions, broadcast Ping collisions, reply timing,
// Response level, REG WRITE/ACTION, Restart and FEETECH's own instructions (docs/feetech.md
// "On a bus"; the status bits and protections: feetech_protection_test.cpp; refusals:
// feetech_refusals_test.cpp).
#include <catch2/catch.hpp>

#include "app/daemon/bus_state.hpp"
#include "feetech_rig.hpp"

namespace dxlemu {

using namespace std::chrono_literals;
using namespace test::feetech;
using test::BusRig;
using test::kBroadcast;
using test::line;

TEST_CASE("A FEETECH Ping is answered with FF FF ID 02 ERR SUM after wire and processing time",
          "[bus][feetech][timing]") {
  BusRig rig;
  sts_bus(rig, 1);
  const std::size_t sent = send(rig, 1, wire::Ping{});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 1);
  CHECK(d[0].bytes == std::vector<std::uint8_t>{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  // Return delay (address 7) 0 at the factory.
  CHECK(d[0].at == sim::SimTime{} + line(sent, kRate) + kProcessing + line(6, kRate));
}

TEST_CASE("A FEETECH servo reads its model number at 3 and answers Read with its bytes",
          "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 1);
  send(rig, 1, wire::Read{3, 2});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(status(rig.link.deliveries()[0]) == "id=1 error=0x00 params=09 03");  // 777
}

TEST_CASE("Broadcast Ping: one FEETECH servo answers cleanly, several collide",
          "[bus][feetech][collision]") {
  SECTION("one servo") {
    BusRig rig;
    sts_bus(rig, 1);
    send(rig, kBroadcast, wire::Ping{});
    rig.run();
    REQUIRE(rig.link.deliveries().size() == 1);
    CHECK(status(rig.link.deliveries()[0]) == "id=1 error=0x00");
  }
  SECTION("six servos") {
    BusRig rig;
    sts_bus(rig, 6);
    send(rig, kBroadcast, wire::Ping{});
    rig.run();
    // All six answer at once: the client gets one garbled packet (the line's wired AND of the
    // six), whose checksum fails, not six statuses.
    REQUIRE(rig.link.deliveries().size() == 1);
    CHECK(rig.link.deliveries()[0].bytes ==
          std::vector<std::uint8_t>{0xFF, 0xFF, 0x00, 0x02, 0x00, 0xF0});
    CHECK(status(rig.link.deliveries()[0]) == "not one status packet");
    CHECK(rig.bus.stats().id_conflicts == 1);
  }
}

TEST_CASE("FEETECH SYNC READ answers one status per listed ID, in request order, chained",
          "[bus][feetech][timing]") {
  BusRig rig;
  sts_bus(rig, 3);
  for (const auto& servo : rig.bus.servos()) {
    servo->table().set("present_temperature", 30 + servo->id());
  }
  rig.bus.servos()[2]->table().set("return_delay_time", 10);  // ID 3: 20 us
  rig.bus.servos()[2]->commit_deferred();
  const std::size_t sent = send(rig, kBroadcast, wire::SyncRead{63, 1, {3, 1, 2}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 3);
  CHECK(status(d[0]) == "id=3 error=0x00 params=21");
  CHECK(status(d[1]) == "id=1 error=0x00 params=1F");
  CHECK(status(d[2]) == "id=2 error=0x00 params=20");
  const sim::SimTime first =
      sim::SimTime{} + line(sent, kRate) + kProcessing + 20us + line(7, kRate);
  CHECK(d[0].at == first);
  CHECK(d[1].at == first + kProcessing + line(7, kRate));
  CHECK(d[2].at == d[1].at + kProcessing + line(7, kRate));
}

TEST_CASE("A FEETECH SYNC READ stops at a listed ID that does not answer, as the 2.0 chain does",
          "[bus][feetech]") {
  BusRig rig;
  rig.add("feetech/sts3215", 1);
  rig.add("feetech/sts3215", 3);
  send(rig, kBroadcast, wire::SyncRead{56, 2, {1, 2, 3}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(status(rig.link.deliveries()[0]).rfind("id=1 ", 0) == 0);
}

TEST_CASE("FEETECH SYNC WRITE and broadcast WRITE apply without a reply", "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 2);
  send(rig, kBroadcast, wire::SyncWrite{41, 1, {{1, {10}}, {2, {20}}}});
  rig.run();
  send(rig, kBroadcast, wire::Write{26, {3}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.servos()[0]->table().get("acceleration") == 10);
  CHECK(rig.bus.servos()[1]->table().get("acceleration") == 20);
  CHECK(rig.bus.servos()[1]->table().get("positive_deadband") == 3);
}

TEST_CASE("FEETECH Response level 0 answers READ and PING only", "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 1);
  rig.bus.servos()[0]->table().set("response_status_level", 0);
  send(rig, 1, wire::Write{41, {5}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.servos()[0]->table().get("acceleration") == 5);
  send(rig, 1, wire::Read{41, 1});
  rig.run();
  send(rig, 1, wire::Ping{});
  rig.run();
  send(rig, kBroadcast, wire::SyncRead{41, 1, {1}});
  rig.run();
  CHECK(rig.link.deliveries().size() == 3);
}

TEST_CASE("FEETECH REG WRITE sets the Async write flag, ACTION applies it and clears it",
          "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 2);
  send(rig, 1, wire::RegWrite{41, {7}});
  rig.run();
  send(rig, 2, wire::RegWrite{41, {9}});
  rig.run();
  for (const auto& servo : rig.bus.servos()) {
    CHECK(servo->table().get("async_write_flag") == 1);
    CHECK(servo->table().get("acceleration") == 0);
  }
  rig.link.clear();
  send(rig, kBroadcast, wire::Action{});
  rig.run();
  CHECK(rig.link.deliveries().empty());  // broadcast: "returns no data frame"
  CHECK(rig.bus.servos()[0]->table().get("acceleration") == 7);
  CHECK(rig.bus.servos()[1]->table().get("acceleration") == 9);
  CHECK(rig.bus.servos()[0]->table().get("async_write_flag") == 0);
}

TEST_CASE("FEETECH Restart sends no status and the servo is silent for its 1800 ms boot",
          "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 1);
  rig.bus.servos()[0]->table().set("acceleration", 33);
  send(rig, 1, wire::Reboot{});
  rig.run(10ms);
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.booting(*rig.bus.servos()[0]));
  CHECK(rig.bus.servos()[0]->table().get("acceleration") == 0);  // RAM back to its initial value
  rig.run(1790ms);
  send(rig, 1, wire::Ping{});
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("Return delay in 2 us units, SMS counts a value below 50 as 50, HLS has none",
          "[bus][feetech][timing]") {
  const auto reply_after = [](const std::string& model, std::optional<std::int64_t> delay) {
    BusRig rig;
    model::Servo& servo = rig.add(model, 1);
    if (delay) {
      servo.table().set("return_delay_time", *delay);
      servo.commit_deferred();
    }
    const std::size_t sent = send(rig, 1, wire::Ping{});
    rig.run();
    REQUIRE(rig.link.deliveries().size() == 1);
    return rig.link.deliveries()[0].at - sim::SimTime{} - line(sent, kRate) - line(6, kRate) -
           kProcessing;
  };
  CHECK(reply_after("feetech/sts3215", 10) == 20us);
  CHECK(reply_after("feetech/sts3215", 0) == 0us);
  CHECK(reply_after("feetech/sm8512bl", 0) == 100us);
  CHECK(reply_after("feetech/sm8512bl", 60) == 120us);
  CHECK(reply_after("feetech/hls3625m", std::nullopt) == 0us);
}

TEST_CASE("An STS3215 moves to its goal: Present = Actual - Position offset",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{55, {0}});                 // Lock 0
  ask(rig, 1, wire::Write{31, le16(0x0800 | 100)});  // Position offset -100 (sign bit 11)
  CHECK(servo.table().get("position_offset") == -100);
  CHECK(servo.table().get("present_position") == 2148);  // the shaft at 2048, minus -100
  ask(rig, 1, wire::Write{40, {1}});
  ask(rig, 1, wire::Write{42, le16(3000)});
  rig.run(2s);
  rig.bus.catch_up();
  CHECK(std::abs(servo.table().get("present_position") - 3000) <= 2);
  CHECK(servo.table().get("moving_flag") == 0);
}

TEST_CASE("STS Operating mode 1 turns at Running speed, 2 drives open-loop PWM",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{33, {1}});                 // constant speed (wheel)
  ask(rig, 1, wire::Write{46, le16(0x8000 | 300)});  // -300 steps/s (sign bit 15)
  ask(rig, 1, wire::Write{40, {1}});
  rig.run(1s);
  rig.bus.catch_up();
  CHECK(std::abs(servo.table().get("present_speed") + 300) <= 3);
  CHECK(servo.table().get("moving_flag") == 1);
  ask(rig, 1, wire::Write{33, {2}});  // PWM open loop
  ask(rig, 1, wire::Write{44, le16(500)});
  rig.run(1s);
  rig.bus.catch_up();
  CHECK(servo.table().get("present_speed") > 0);
}

TEST_CASE("STS step mode moves Goal position steps from the shaft and reads the steps to go",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{33, {3}});
  ask(rig, 1, wire::Write{40, {1}});
  rig.bus.catch_up();
  CHECK(servo.table().get("present_position") == 0);  // holding: nothing to go
  ask(rig, 1, wire::Write{42, le16(5000)});           // more than a turn
  rig.run(200ms);
  rig.bus.catch_up();
  const std::int64_t to_go = servo.table().get("present_position");
  CHECK(to_go > 0);
  CHECK(to_go < 5000);
  CHECK(servo.table().get("moving_flag") == 1);
  rig.run(5s);
  rig.bus.catch_up();
  CHECK(std::abs(servo.table().get("present_position")) <= 2);
  CHECK(servo.table().get("moving_flag") == 0);
  ask(rig, 1, wire::Write{42, le16(0x8000 | 1500)});  // -1500 (sign bit 15)
  rig.run(200ms);
  send(rig, 1, wire::Read{56, 2});
  rig.run();
  // Going back: the steps to go are negative, sign-magnitude on the wire.
  const auto& reply = rig.link.deliveries().back().bytes;
  REQUIRE(reply.size() == 8);
  CHECK((reply[6] & 0x80) != 0);
  rig.run(5s);
  ask(rig, 1, wire::Write{33, {0}});  // position mode: Present position is the place again,
  rig.bus.catch_up();                 // within one turn
  CHECK(std::abs(servo.table().get("present_position") - (2048 + 5000 - 1500) % 4096) <= 4);
}

TEST_CASE("FEETECH position mode stops at the angle limits, both 0 lift them",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{55, {0}});
  ask(rig, 1, wire::Write{9, le16(1000)});
  ask(rig, 1, wire::Write{11, le16(3000)});
  ask(rig, 1, wire::Write{40, {1}});
  ask(rig, 1, wire::Write{42, le16(3500)});
  CHECK(servo.table().get("goal_position") == 3500);  // kept as written, no refusal
  rig.run(2s);
  rig.bus.catch_up();
  CHECK(std::abs(servo.table().get("present_position") - 3000) <= 2);
  ask(rig, 1, wire::Write{42, le16(200)});
  rig.run(2s);
  rig.bus.catch_up();
  CHECK(std::abs(servo.table().get("present_position") - 1000) <= 2);
  ask(rig, 1, wire::Write{9, le16(0)});
  ask(rig, 1, wire::Write{11, le16(0)});  // multi-turn: no limit
  ask(rig, 1, wire::Write{42, le16(6000)});
  rig.run(5s);
  rig.bus.catch_up();
  // Single-turn feedback (Phase 12): the shaft went 5000 steps on, and reads the angle there.
  CHECK(std::abs(servo.table().get("present_position") - (6000 - 4096)) <= 2);
  ask(rig, 1, wire::Write{18, {12 | 16}});  // full-angle feedback: the turns show
  CHECK(std::abs(servo.table().get("present_position") - 6000) <= 2);
}

TEST_CASE("STS Torque switch 128 calibrates Present Position to 2048", "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{40, {1}});
  ask(rig, 1, wire::Write{42, le16(1000)});
  rig.run(2s);
  rig.bus.catch_up();
  REQUIRE(std::abs(servo.table().get("present_position") - 1000) <= 2);
  ask(rig, 1, wire::Write{40, {128}});
  CHECK(servo.table().get("present_position") == 2048);
  // A command, not a state: bit 7 clears, and the item reads 0, torque off.
  CHECK(servo.table().get("torque_switch") == 0);
  CHECK(servo.table().get("goal_position") == 1000);
}

TEST_CASE("FEETECH position calibration, status reset, parameter backup and recovery",
          "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::PositionCalibration{1024});
  CHECK(servo.table().get("present_position") == 1024);
  ask(rig, 1, wire::PositionCalibration{});
  CHECK(servo.table().get("present_position") == 2048);
  ask(rig, 1, wire::StatusReset{});
  // Backup and recovery need the EEPROM unlocked (Lock 0); recovery keeps the ID.
  ask(rig, 1, wire::Write{55, {0}});
  ask(rig, 1, wire::Write{26, {5}});
  ask(rig, 1, wire::ParameterBackup{});
  ask(rig, 1, wire::Write{26, {9}});
  ask(rig, 1, wire::Write{5, {7}});
  REQUIRE(servo.id() == 7);
  ask(rig, 7, wire::ParameterRecovery{});
  CHECK(servo.table().get("positive_deadband") == 5);
  CHECK(servo.id() == 7);
  ask(rig, 7, wire::Write{55, {1}});
  ask(rig, 7, wire::Write{26, {11}});
  ask(rig, 7, wire::ParameterRecovery{});  // locked: refused
  rig.run();
  CHECK(servo.table().get("positive_deadband") == 11);
  // Every one of them was answered.
  CHECK(rig.link.deliveries().size() == 12);
}

TEST_CASE(
    "FEETECH Lock: EEPROM writes are never refused; only those made at Lock 0 survive power-off",
    "[bus][feetech][lock]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  REQUIRE(servo.table().get("lock_flag") == 1);  // the wiki's initial value
  ask(rig, 1, wire::Write{26, {4}});             // Positive deadband, EEPROM, while locked
  ask(rig, 1, wire::Write{55, {0}});
  ask(rig, 1, wire::Write{27, {6}});  // Negative deadband, while unlocked
  ask(rig, 1, wire::Write{55, {1}});
  REQUIRE(rig.link.deliveries().size() == 4);
  for (const auto& d : rig.link.deliveries()) {
    CHECK(status(d) == "id=1 error=0x00");
  }
  CHECK(servo.table().get("positive_deadband") == 4);  // in effect until power-off
  // The state file (--state) keeps what a power cycle keeps.
  const app::ServoState state = app::capture_state(servo.table());
  const auto value_in_state = [&](const std::string& key) {
    for (const auto& [k, v] : state.eeprom) {
      if (k == key) {
        return v;
      }
    }
    return std::int64_t{-1};
  };
  CHECK(value_in_state("positive_deadband") == 1);
  CHECK(value_in_state("negative_deadband") == 6);
  rig.bus.power_on(servo);
  rig.run(2s);
  CHECK(servo.table().get("positive_deadband") == 1);
  CHECK(servo.table().get("negative_deadband") == 6);
  CHECK(servo.table().get("lock_flag") == 1);
}

TEST_CASE("A new ID written while locked answers at once and is gone after a Restart",
          "[bus][feetech][lock]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{5, {9}});
  CHECK(servo.id() == 9);
  ask(rig, 9, wire::Reboot{});
  rig.run(2s);
  CHECK(servo.id() == 1);
}

}  // namespace dxlemu
