// Servo::eeprom_writes: how many times bus instructions wrote each EEPROM item (the flash wear a
// web page shows), counted once where every instruction's write lands (model/servo.cpp).
#include <catch2/catch.hpp>

#include "bus_write.hpp"
#include "model/servo.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using model::Servo;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::size_t index_of(const Servo& servo, const std::string& key) {
  return *servo.spec().index_of(key);
}

std::uint64_t writes(const Servo& servo, const std::string& key) {
  return servo.eeprom_writes(index_of(servo, key));
}

model::ServoResponse run(Servo& servo, wire::Instruction instruction) {
  return servo.execute(
      {servo.protocol().value_or(wire::Protocol::V2), servo.id(), std::move(instruction)},
      model::Addressing::Unicast);
}

}  // namespace

TEST_CASE("A Write of an EEPROM item counts once per Write, changed or not, and RAM is not counted",
          "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  CHECK(writes(servo, "return_delay_time") == 0);
  CHECK(test::bus_write(servo, "return_delay_time", 3) == 0);
  CHECK(writes(servo, "return_delay_time") == 1);
  CHECK(test::bus_write(servo, "return_delay_time", 3) == 0);  // the same value: still a write
  CHECK(writes(servo, "return_delay_time") == 2);
  CHECK(test::bus_write(servo, "goal_position", 1000) == 0);
  CHECK(writes(servo, "goal_position") == 0);
  CHECK(writes(servo, "id") == 0);  // untouched items stay at 0
}

TEST_CASE("A Write that touches several EEPROM items counts each of them",
          "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  // Max Position Limit (48, 4 bytes) and Min Position Limit (52, 4 bytes) in one Write.
  Bytes data = {0xFF, 0x0F, 0, 0, 0, 0, 0, 0};
  REQUIRE(run(servo, wire::Write{48, data}).error == 0);
  CHECK(writes(servo, "max_position_limit") == 1);
  CHECK(writes(servo, "min_position_limit") == 1);
}

TEST_CASE("A refused write is not counted: EEPROM locked while torque is on",
          "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  REQUIRE(test::bus_write(servo, "torque_enable", 1) == 0);
  CHECK(test::bus_write(servo, "return_delay_time", 3) != 0);  // Access Error
  CHECK(writes(servo, "return_delay_time") == 0);
}

TEST_CASE("The control API's device-side write and Factory Reset are not counted",
          "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  servo.device_write(index_of(servo, "return_delay_time"), 10);
  CHECK(servo.table().get("return_delay_time") == 10);
  CHECK(writes(servo, "return_delay_time") == 0);
  REQUIRE(test::bus_write(servo, "return_delay_time", 3) == 0);
  REQUIRE(run(servo, wire::FactoryReset{0xFF}).error == 0);
  CHECK(servo.table().get("return_delay_time") == 250);  // reset, but not a counted write
  CHECK(writes(servo, "return_delay_time") == 1);
}

TEST_CASE(
    "Reg Write counts when Action writes, Sync/Bulk Write parts count, and a reboot keeps "
    "the counts",
    "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  REQUIRE(run(servo, wire::RegWrite{9, {5}}).error == 0);  // Return Delay Time
  CHECK(writes(servo, "return_delay_time") == 0);          // registered, not yet written
  REQUIRE(run(servo, wire::Action{}).error == 0);
  CHECK(writes(servo, "return_delay_time") == 1);
  servo.write_part(9, Bytes{6});  // this servo's block of a Sync or Bulk Write
  CHECK(writes(servo, "return_delay_time") == 2);
  servo.reboot();
  CHECK(writes(servo, "return_delay_time") == 2);
}

TEST_CASE("A FEETECH Write of an EEPROM item counts as DYNAMIXEL's does",
          "[model][eeprom_writes]") {
  Servo servo(test::shipped_model("feetech/sts3215"), 1);
  REQUIRE(servo.protocol() == wire::Protocol::Feetech);
  run(servo, wire::Write{7, {10}});  // Return delay time
  CHECK(servo.table().get("return_delay_time") == 10);
  CHECK(writes(servo, "return_delay_time") == 1);
  run(servo, wire::Write{42, {0, 8}});  // Goal position: RAM
  CHECK(writes(servo, "goal_position") == 0);
}
