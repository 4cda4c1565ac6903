// FEETECH status bits and protections on a bus (docs/feetech.md "Status bits"): the bits in the
// error byte of every reply, and how each protection acts on the motor and ends
// (feetech/field-behaviour.md row 7): overload and overcurrent at the next position command,
// over-voltage when the supply is back within its limits, over-temperature by switching the
// torque off. All on the virtual clock.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "feetech_rig.hpp"
#include "model/motion/hardware_fault.hpp"

namespace dxlemu {
namespace {

using namespace std::chrono_literals;
using namespace test::feetech;

constexpr std::uint8_t kFtBroadcast = test::kBroadcast;

// STS3215 items (models/feetech/sts3215.json).
constexpr std::uint16_t kUnloadCondition = 19;
constexpr std::uint16_t kProtectionCurrent = 28;
constexpr std::uint16_t kOperatingMode = 33;
constexpr std::uint16_t kOvercurrentTime = 38;
constexpr std::uint16_t kTorqueSwitch = 40;
constexpr std::uint16_t kGoalPosition = 42;
constexpr std::uint16_t kRunningSpeed = 46;
constexpr std::uint16_t kTorqueLimit = 48;
constexpr std::uint16_t kLock = 55;
constexpr std::uint16_t kPresentPosition = 56;
constexpr std::uint16_t kPresentLoad = 60;
constexpr std::uint16_t kPresentTemperature = 63;
constexpr std::uint16_t kServoStatus = 65;

// Unload condition at the factory: overheat (4), current (8) and load (32); no voltage (1) and
// no encoder (2).
constexpr std::uint8_t kFactoryUnload = 44;
constexpr std::uint8_t kVoltageBit = 0x01;
constexpr std::uint8_t kEncoderBit = 0x02;

/// Sets the winding's temperature, as the control API's set of Present temperature does.
void heat_winding(model::Servo& servo, std::int64_t celsius) {
  servo.table().set("present_temperature", celsius);
  servo.motion().wake();
}

/// One STS3215 at ID 1, torque on, pushing its blocked shaft towards 3000 with all it has.
model::Servo& blocked_at_full_torque(test::BusRig& rig) {
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  block_shaft(servo, true);
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
  return servo;
}

}  // namespace

TEST_CASE("FEETECH status bits ride in the error byte of PING and READ replies",
          "[bus][feetech][faults]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  ask(rig, 1, wire::Ping{});
  CHECK(last_status(rig) == "id=1 error=0x00");
  heat_winding(servo, 75);  // over Maximum temperature limit (70)
  rig.run(10ms);
  ask(rig, 1, wire::Ping{});
  CHECK(last_status(rig) == "id=1 error=0x04");
  ask(rig, 1, wire::Read{kPresentTemperature, 1});
  CHECK(last_status(rig) == "id=1 error=0x04 params=4B");
  ask(rig, 1, wire::Read{kServoStatus, 1});
  CHECK(last_status(rig) == "id=1 error=0x04 params=04");
}

TEST_CASE("A FEETECH SYNC READ returns its data with the status bits set",
          "[bus][feetech][faults]") {
  test::BusRig rig;
  model::Servo& hot = rig.add("feetech/sts3215", 1);
  rig.add("feetech/sts3215", 2);
  heat_winding(hot, 75);
  rig.run(10ms);
  rig.link.clear();
  send(rig, kFtBroadcast, wire::SyncRead{kPresentPosition, 2, {1, 2}});
  rig.run(10ms);
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  // Both at 2048 (00 08); a client that ignores the error byte (LeRobot's sync_read) reads both.
  CHECK(test::status_text(d[0].bytes, wire::Protocol::Feetech) == "id=1 error=0x04 params=00 08");
  CHECK(test::status_text(d[1].bytes, wire::Protocol::Feetech) == "id=2 error=0x00 params=00 08");
}

TEST_CASE("A FEETECH overload leaves Holding torque until the next position command",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = blocked_at_full_torque(rig);
  rig.run(1900ms);
  CHECK(item_now(rig, servo, "servo_status") == 0);
  CHECK(item_now(rig, servo, "present_load") == 1000);
  rig.run(200ms);  // past Protection time, 200 x 10 ms, over Overload torque (80 %)
  ask(rig, 1, wire::Read{kPresentLoad, 2});
  CHECK(last_status(rig) == "id=1 error=0x20 params=C8 00");  // Holding torque: 20.0 %
  CHECK(item_now(rig, servo, "torque_limit") == 1000);        // not rewritten
  CHECK(item_now(rig, servo, "torque_switch") == 1);

  SECTION("it outlasts the load, and a Goal position write ends it") {
    block_shaft(servo, false);
    rig.run(3s);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x20");
    CHECK(item_now(rig, servo, "servo_status") == 0x20);
    // Holding torque is enough for the free shaft: it gets there, tripped.
    CHECK(std::abs(item_now(rig, servo, "present_position") - 3000) <= 2);
    // The goal write's own status is already clean.
    ask(rig, 1, wire::Write{kGoalPosition, le16(1000)});
    CHECK(last_status(rig) == "id=1 error=0x00");
    CHECK(item_now(rig, servo, "servo_status") == 0);
    rig.run(3s);
    CHECK(std::abs(item_now(rig, servo, "present_position") - 1000) <= 2);
  }
  SECTION("a shaft still blocked gets its full torque back and trips it again") {
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x00");
    rig.run(100ms);  // the new move's error builds up: the full torque
    CHECK(item_now(rig, servo, "present_load") == 1000);
    rig.run(1800ms);
    CHECK(item_now(rig, servo, "servo_status") == 0);
    rig.run(200ms);
    CHECK(item_now(rig, servo, "servo_status") == 0x20);
    CHECK(item_now(rig, servo, "present_load") == 200);
  }
  SECTION("a SYNC WRITE of Goal position ends it") {
    send(rig, kFtBroadcast, wire::SyncWrite{kGoalPosition, 2, {{1, le16(3000)}}});
    rig.run(100ms);
    CHECK(item_now(rig, servo, "servo_status") == 0);
    CHECK(item_now(rig, servo, "present_load") == 1000);
  }
  SECTION("a REG WRITE of Goal position does not, its ACTION does") {
    ask(rig, 1, wire::RegWrite{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x20");
    ask(rig, 1, wire::Action{});
    CHECK(last_status(rig) == "id=1 error=0x00");
    rig.run(100ms);
    CHECK(item_now(rig, servo, "present_load") == 1000);
  }
  SECTION("other writes do not: Running speed in position mode, Torque switch off and on") {
    ask(rig, 1, wire::Write{kRunningSpeed, le16(500)});
    CHECK(last_status(rig) == "id=1 error=0x20");
    ask(rig, 1, wire::Write{kTorqueSwitch, {0}});
    ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
    CHECK(last_status(rig) == "id=1 error=0x20");
    CHECK(item_now(rig, servo, "servo_status") == 0x20);
  }
}

TEST_CASE("Without the load bit in Unload condition a FEETECH overload only shows while it lasts",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  block_shaft(servo, true);
  ask(rig, 1, wire::Write{kUnloadCondition, {kFactoryUnload & ~0x20}});
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
  rig.run(2100ms);
  CHECK(item_now(rig, servo, "servo_status") == 0x20);
  CHECK(item_now(rig, servo, "present_load") == 1000);  // full torque: nothing tripped
  block_shaft(servo, false);
  rig.run(10ms);
  CHECK(item_now(rig, servo, "servo_status") == 0);  // no longer over Overload torque
}

TEST_CASE("A FEETECH overcurrent cuts the output until the next position command",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  block_shaft(servo, true);
  ask(rig, 1, wire::Write{kLock, {0}});
  ask(rig, 1, wire::Write{kProtectionCurrent, le16(100)});  // 650 mA
  ask(rig, 1, wire::Write{kOvercurrentTime, {50}});         // 500 ms
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
  rig.run(450ms);
  CHECK(item_now(rig, servo, "servo_status") == 0);
  CHECK(item_now(rig, servo, "present_current") >= 100);
  rig.run(100ms);
  // Current (8), selected in Unload condition (44): the output is off, the items as written.
  CHECK(item_now(rig, servo, "servo_status") == 0x08);
  CHECK(item_now(rig, servo, "present_current") == 0);
  CHECK(item_now(rig, servo, "present_load") == 0);
  CHECK(item_now(rig, servo, "torque_limit") == 1000);
  CHECK(item_now(rig, servo, "torque_switch") == 1);

  SECTION("the bit and the cut outlast the current; a Goal position write ends them") {
    block_shaft(servo, false);
    rig.run(1s);
    ask(rig, 1, wire::Read{kPresentPosition, 2});
    CHECK(last_status(rig) == "id=1 error=0x08 params=00 08");  // unloaded: still at 2048
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x00");
    rig.run(2s);
    CHECK(std::abs(item_now(rig, servo, "present_position") - 3000) <= 2);
    CHECK(item_now(rig, servo, "servo_status") == 0);
  }
  SECTION("a shaft still blocked draws the current again and trips it again") {
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x00");
    rig.run(100ms);
    CHECK(item_now(rig, servo, "present_current") >= 100);
    rig.run(500ms);
    CHECK(item_now(rig, servo, "servo_status") == 0x08);
    CHECK(item_now(rig, servo, "present_current") == 0);
  }
}

TEST_CASE("A FEETECH supply out of its limits unloads the motor until it is back within them",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  ask(rig, 1, wire::Write{kGoalPosition, le16(1000)});
  rig.run(2s);
  REQUIRE(std::abs(item_now(rig, servo, "present_position") - 1000) <= 2);

  SECTION("with the voltage bit in Unload condition") {
    ask(rig, 1, wire::Write{kUnloadCondition, {kFactoryUnload | kVoltageBit}});
    set_supply(servo, 9.0);  // over Maximum input voltage, 8.0 V
    rig.run(10ms);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x01");
    // A goal write does not end it, and the unloaded motor does not move.
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x01");
    rig.run(2s);
    CHECK(std::abs(item_now(rig, servo, "present_position") - 1000) <= 2);
    CHECK(item_now(rig, servo, "torque_switch") == 1);
    CHECK(item_now(rig, servo, "torque_limit") == 1000);
    // The supply back within its limits: the bit goes and the motor goes on by itself.
    set_supply(servo, 7.4);
    rig.run(10ms);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x00");
    rig.run(2s);
    CHECK(std::abs(item_now(rig, servo, "present_position") - 3000) <= 2);
  }
  SECTION("at the factory Unload condition (no voltage bit) the bit shows and the motor moves") {
    set_supply(servo, 3.5);  // under Minimum input voltage, 4.0 V
    rig.run(10ms);
    ask(rig, 1, wire::Write{kGoalPosition, le16(1500)});
    CHECK(last_status(rig) == "id=1 error=0x01");
    rig.run(3s);
    CHECK(std::abs(item_now(rig, servo, "present_position") - 1500) <= 2);
  }
}

TEST_CASE("A FEETECH over-temperature switches the torque off, its bit stays while it is hot",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  ask(rig, 1, wire::Write{kGoalPosition, le16(1000)});
  rig.run(2s);
  heat_winding(servo, 75);
  rig.run(10ms);
  ask(rig, 1, wire::Read{kTorqueSwitch, 1});
  CHECK(last_status(rig) == "id=1 error=0x04 params=00");
  CHECK(item_now(rig, servo, "torque_limit") == 1000);
  // Switched on while still hot: accepted, and off again at the next tick.
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  CHECK(last_status(rig) == "id=1 error=0x04");
  CHECK(item_now(rig, servo, "torque_switch") == 0);
  rig.run(5s);  // cooling towards 25 degrees: still over 70
  CHECK(item_now(rig, servo, "servo_status") == 0x04);
  rig.run(60s);
  ask(rig, 1, wire::Ping{});
  CHECK(last_status(rig) == "id=1 error=0x00");
  CHECK(item_now(rig, servo, "torque_switch") == 0);  // the torque stays off: it was switched off
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  rig.run(10ms);
  CHECK(item_now(rig, servo, "torque_switch") == 1);
}

TEST_CASE("Injected FEETECH errors last while their rule lasts, whatever the client sends",
          "[bus][feetech][faults][motion]") {
  using model::HardwareFault;
  test::BusRig rig;
  model::Servo& servo = blocked_at_full_torque(rig);
  rig.run(100ms);
  REQUIRE(item_now(rig, servo, "present_load") == 1000);

  SECTION("overload: Holding torque while injected, through a position command") {
    servo.motion().set_injected(model::fault_set(HardwareFault::Overload));
    rig.run(10ms);
    ask(rig, 1, wire::Read{kPresentLoad, 2});
    CHECK(last_status(rig) == "id=1 error=0x20 params=C8 00");
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x20");
    servo.motion().set_injected(0);
    rig.run(100ms);  // the move the goal write restarted has built up its error again
    ask(rig, 1, wire::Read{kPresentLoad, 2});
    CHECK(last_status(rig) == "id=1 error=0x00 params=E8 03");  // full torque again
  }
  SECTION("overcurrent: the output off while injected, through a position command") {
    servo.motion().set_injected(model::fault_set(HardwareFault::ElectricalShock));
    rig.run(10ms);
    ask(rig, 1, wire::Write{kGoalPosition, le16(3000)});
    CHECK(last_status(rig) == "id=1 error=0x08");
    CHECK(item_now(rig, servo, "present_load") == 0);
    servo.motion().set_injected(0);
    rig.run(100ms);
    CHECK(item_now(rig, servo, "servo_status") == 0);
    CHECK(item_now(rig, servo, "present_load") == 1000);
  }
  SECTION("encoder (selected): unloaded until Torque limit is written, as before") {
    ask(rig, 1, wire::Write{kUnloadCondition, {kFactoryUnload | kEncoderBit}});
    servo.motion().set_injected(model::fault_set(HardwareFault::Encoder));
    rig.run(10ms);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x02");
    CHECK(item_now(rig, servo, "present_load") == 0);
    servo.motion().set_injected(0);
    rig.run(10ms);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x00");
    CHECK(item_now(rig, servo, "present_load") == 0);
    CHECK(item_now(rig, servo, "torque_limit") == 1000);  // never rewritten
    ask(rig, 1, wire::Write{kTorqueLimit, le16(1000)});
    CHECK(item_now(rig, servo, "present_load") == 1000);
  }
  SECTION("encoder (not selected at the factory): only the bit") {
    servo.motion().set_injected(model::fault_set(HardwareFault::Encoder));
    rig.run(10ms);
    ask(rig, 1, wire::Ping{});
    CHECK(last_status(rig) == "id=1 error=0x02");
    CHECK(item_now(rig, servo, "present_load") == 1000);
  }
}

TEST_CASE("In FEETECH wheel mode a Running speed write is the command that ends an overload",
          "[bus][feetech][faults][motion]") {
  test::BusRig rig;
  model::Servo& servo = rig.add("feetech/sts3215", 1);
  model::Conditions c = servo.motion().conditions();
  c.external_load_nm = -4;  // more than the motor's 1.86 N·m, against the wheel
  servo.motion().set_conditions(c);
  ask(rig, 1, wire::Write{kOperatingMode, {1}});
  ask(rig, 1, wire::Write{kRunningSpeed, le16(1000)});
  ask(rig, 1, wire::Write{kTorqueSwitch, {1}});
  rig.run(2100ms);
  CHECK(item_now(rig, servo, "servo_status") == 0x20);
  CHECK(item_now(rig, servo, "present_load") == 200);
  ask(rig, 1, wire::Write{kRunningSpeed, le16(1000)});
  CHECK(last_status(rig) == "id=1 error=0x00");
  CHECK(item_now(rig, servo, "present_load") == 1000);
}

}  // namespace dxlemu
