// The STS3215 behaviours LeRobot users meet (../shared/reference/feetech/field-behaviour.md):
// single-turn and full-angle feedback (Phase bit 4), a goal write turning torque on, goals
// clamped to the angle limits around the turn, torque on driving to the goal as it stands, the
// reply to an ID write, the firmware bytes (docs/feetech.md "Field behaviour").
#include <catch2/catch.hpp>

#include "feetech_rig.hpp"

namespace dxlemu {
namespace field_behaviour {

using namespace std::chrono_literals;
using namespace test::feetech;
using test::BusRig;

constexpr std::int64_t kTurn = 4096;
constexpr std::uint8_t kFullAngle = 12 | 16;  // the factory Phase with bit 4 set

/// `bytes` as status_text prints parameters: "E8 83".
std::string hex_bytes(const std::vector<std::uint8_t>& bytes) {
  std::string text;
  for (const std::uint8_t b : bytes) {
    constexpr std::string_view kDigits = "0123456789ABCDEF";
    if (!text.empty()) {
      text += ' ';
    }
    text += kDigits[b >> 4];
    text += kDigits[b & 0x0F];
  }
  return text;
}

/// Present position as it is now (the motion caught up first).
std::int64_t present(model::Servo& servo, BusRig& rig) {
  return item_now(rig, servo, "present_position");
}

}  // namespace field_behaviour

using namespace field_behaviour;

TEST_CASE("Phase bit 4 clear: Present position is the angle within one turn, wrapping at 4095",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  REQUIRE(servo.table().get("phase") == 12);  // the factory value: bit 4 clear
  turn_by_hand_to(rig, servo, 4090);
  CHECK(present(servo, rig) == 4090);
  turn_by_hand_to(rig, servo, 4095);
  turn_by_hand_to(rig, servo, 3);  // on across the seam, not a turn back
  CHECK(present(servo, rig) == 3);
  // Position offset applies around the turn: 3 - 100 reads 4095 - 96.
  ask(rig, 1, wire::Write{31, {100, 0}});
  CHECK(present(servo, rig) == kTurn - 97);
  ask(rig, 1, wire::Read{56, 2});
  CHECK(last_status(rig) == "id=1 error=0x00 params=9F 0F");
  // The shaft went on across the seam: full-angle feedback shows the turn it is on.
  ask(rig, 1, wire::Write{18, {kFullAngle}});
  CHECK(present(servo, rig) == kTurn - 97);
  ask(rig, 1, wire::Write{31, {0, 0}});
  CHECK(present(servo, rig) == kTurn + 3);
}

TEST_CASE("Phase bit 4 set: the turns count beyond 4095 and below 0, lost at power-off",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{55, {0}});  // Lock 0: Phase survives the power cycle
  ask(rig, 1, wire::Write{18, {kFullAngle}});
  ask(rig, 1, wire::Write{11, sm16(0)});  // both limits 0: multi-turn goals
  ask(rig, 1, wire::Write{40, {1}});
  ask(rig, 1, wire::Write{42, sm16(2 * kTurn + 100)});
  rig.run(6s);
  CHECK(std::abs(present(servo, rig) - (2 * kTurn + 100)) <= 2);
  ask(rig, 1, wire::Write{42, sm16(-1000)});
  rig.run(6s);
  CHECK(std::abs(present(servo, rig) + 1000) <= 2);
  ask(rig, 1, wire::Write{40, {0}});  // hold still for an exact reading
  const std::int64_t below_zero = present(servo, rig);
  REQUIRE(below_zero < 0);
  ask(rig, 1, wire::Read{56, 2});
  CHECK(last_status(rig) == "id=1 error=0x00 params=" + hex_bytes(sm16(below_zero)));
  // Power-off loses the turn count: the shaft reads within one turn again.
  rig.bus.power_on(servo);
  rig.run(2s);
  CHECK(servo.table().get("phase") == kFullAngle);
  CHECK(present(servo, rig) == below_zero + kTurn);
}

TEST_CASE("A goal written with the torque off turns it on and moves the servo",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 2);
  model::Servo& first = *rig.bus.servos()[0];
  model::Servo& second = *rig.bus.servos()[1];
  REQUIRE(first.table().get("torque_switch") == 0);
  ask(rig, 1, wire::Write{42, sm16(3000)});
  CHECK(last_status(rig) == "id=1 error=0x00");
  CHECK(first.table().get("torque_switch") == 1);
  // LeRobot's sync_write("Goal_Position") does the same to every servo it lists.
  ask(rig, test::kBroadcast, wire::SyncWrite{42, 2, {{2, sm16(1000)}}});
  CHECK(second.table().get("torque_switch") == 1);
  rig.run(2s);
  CHECK(std::abs(present(first, rig) - 3000) <= 2);
  CHECK(std::abs(present(second, rig) - 1000) <= 2);

  SECTION("in wheel mode the speed is the goal") {
    ask(rig, 1, wire::Write{40, {0}});
    ask(rig, 1, wire::Write{33, {1}});
    ask(rig, 1, wire::Write{46, sm16(500)});
    CHECK(first.table().get("torque_switch") == 1);
    rig.run(1s);
    rig.bus.catch_up();
    CHECK(std::abs(first.table().get("present_speed") - 500) <= 5);
  }
  SECTION("in position mode Running speed is no goal: the torque stays off") {
    ask(rig, 1, wire::Write{40, {0}});
    ask(rig, 1, wire::Write{46, sm16(500)});
    CHECK(first.table().get("torque_switch") == 0);
  }
}

TEST_CASE("A goal beyond the angle limits drives to the nearer limit around the turn",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{9, sm16(1000)});
  ask(rig, 1, wire::Write{11, sm16(3000)});
  ask(rig, 1, wire::Write{42, sm16(4090)});  // 1006 steps below 1000, 1090 above 3000
  CHECK(last_status(rig) == "id=1 error=0x00");
  CHECK(servo.table().get("goal_position") == 4090);  // kept as written
  rig.run(2s);
  CHECK(std::abs(present(servo, rig) - 1000) <= 2);
  ask(rig, 1, wire::Write{42, sm16(3500)});
  rig.run(2s);
  CHECK(std::abs(present(servo, rig) - 3000) <= 2);
  // LeRobot's "snap the goal to the present position" with the arm pushed outside its limits:
  // the servo drives back inside.
  ask(rig, 1, wire::Write{40, {0}});
  turn_by_hand_to(rig, servo, 3800);
  ask(rig, 1, wire::Write{42, sm16(3800)});
  rig.run(2s);
  CHECK(std::abs(present(servo, rig) - 3000) <= 2);
}

TEST_CASE("Torque on drives to Goal position as it stands, a stale goal too",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  // At power-up Goal position is where the shaft is.
  ask(rig, 1, wire::Read{42, 2});
  CHECK(last_status(rig) == "id=1 error=0x00 params=00 08");
  turn_by_hand_to(rig, servo, 1000);
  ask(rig, 1, wire::Write{40, {1}});
  CHECK(servo.table().get("goal_position") == 2048);
  rig.run(2s);
  CHECK(std::abs(present(servo, rig) - 2048) <= 2);
}

TEST_CASE("Torque switch 128 calibrates to 2048 within one turn and reads 0 afterwards",
          "[bus][feetech][motion]") {
  BusRig rig;
  sts_bus(rig, 1);
  model::Servo& servo = *rig.bus.servos()[0];
  ask(rig, 1, wire::Write{55, {0}});
  ask(rig, 1, wire::Write{18, {kFullAngle}});
  ask(rig, 1, wire::Write{11, sm16(0)});  // both limits 0: multi-turn goals
  ask(rig, 1, wire::Write{40, {1}});
  ask(rig, 1, wire::Write{42, sm16(kTurn + 10)});
  rig.run(3s);
  REQUIRE(std::abs(present(servo, rig) - (kTurn + 10)) <= 2);
  // The shaft is a turn on: full-angle feedback needs an offset of a turn, beyond -2047 ~ 2047.
  ask(rig, 1, wire::Write{40, {128}});
  CHECK(servo.table().get("position_offset") == 0);
  CHECK(servo.table().get("torque_switch") == 0);
  // Single-turn feedback reads the angle: an offset within reach makes it 2048.
  ask(rig, 1, wire::Write{18, {12}});
  ask(rig, 1, wire::Write{40, {128}});
  CHECK(present(servo, rig) == 2048);
  CHECK(std::abs(servo.table().get("position_offset") - (10 - 2048)) <= 2);
}

TEST_CASE("The reply to a write of ID comes from the old ID", "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 1);
  ask(rig, 1, wire::Write{5, {7}});
  CHECK(last_status(rig) == "id=1 error=0x00");
  ask(rig, 7, wire::Ping{});
  CHECK(last_status(rig) == "id=7 error=0x00");
}

TEST_CASE("Every STS3215 of an arm reports the same firmware bytes", "[bus][feetech]") {
  BusRig rig;
  sts_bus(rig, 6);
  for (std::uint8_t id = 1; id <= 6; ++id) {
    ask(rig, id, wire::Read{0, 2});
    CHECK(last_status(rig) == "id=" + std::to_string(id) + " error=0x00 params=03 06");
  }
}

}  // namespace dxlemu
