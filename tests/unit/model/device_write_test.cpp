// The device side of a servo, as the control API uses it: Servo::device_write (a write the bus's
// rules do not refuse, hooks and deferred identity included) and the ControlTable members it
// rests on: encoded, fits, raw_value and the EEPROM change count the state file is kept by.
#include <catch2/catch.hpp>

#include <chrono>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "model/servo.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using model::Servo;

namespace {

struct Written {
  std::int64_t old_value = 0;
  std::int64_t new_value = 0;
  int calls = 0;
};

/// Records every write hook call of `key` in `w`, which must outlive `servo`.
void watch(Servo& servo, std::string_view key, Written& w) {
  servo.table().on_write(key, [&w](std::size_t, std::int64_t old_value, std::int64_t new_value) {
    w.old_value = old_value;
    w.new_value = new_value;
    ++w.calls;
  });
}

std::size_t item(const Servo& servo, std::string_view key) {
  return *servo.spec().index_of(key);
}

}  // namespace

TEST_CASE("A device write a Write instruction could make runs as that Write, hooks included",
          "[model][servo]") {
  Written goal;
  Servo servo(test::shipped_model("xm430-w350"), 1);
  watch(servo, "goal_position", goal);
  servo.device_write(item(servo, "goal_position"), 3000);
  CHECK(servo.table().get("goal_position") == 3000);
  CHECK(goal.calls == 1);
  CHECK(goal.old_value == 2048);
  CHECK(goal.new_value == 3000);
}

TEST_CASE("A device write the bus would refuse is forced into the image, and no hook hears it",
          "[model][servo]") {
  Written hook;
  Servo servo(test::shipped_model("xm430-w350"), 1);
  SECTION("a read-only item") {
    servo.device_write(item(servo, "present_temperature"), 70);
    CHECK(servo.table().get("present_temperature") == 70);
  }
  SECTION("a value outside the item's range") {
    watch(servo, "goal_position", hook);
    servo.device_write(item(servo, "goal_position"), 5000);  // beyond Max Position Limit
    CHECK(servo.table().get("goal_position") == 5000);
    CHECK(hook.calls == 0);
  }
  SECTION("EEPROM while torque is on") {
    servo.device_write(item(servo, "torque_enable"), 1);
    REQUIRE(servo.table().eeprom_locked());
    watch(servo, "operating_mode", hook);
    servo.device_write(item(servo, "operating_mode"), 1);
    CHECK(servo.table().get("operating_mode") == 1);
    CHECK(hook.calls == 0);
  }
}

TEST_CASE("A device write of Indirect Data stays in the item instead of reaching the mapped one",
          "[model][servo]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  servo.table().set("indirect_address_1", 64);  // Torque Enable
  servo.device_write(item(servo, "indirect_data_1"), 1);
  CHECK(servo.table().get("indirect_data_1") == 1);
  CHECK(servo.table().get("torque_enable") == 0);
}

TEST_CASE("A device write of ID, Baud Rate, Return Delay Time or Protocol takes effect at once",
          "[model][servo]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  servo.device_write(item(servo, "id"), 7);
  CHECK(servo.id() == 7);
  servo.device_write(item(servo, "baud_rate"), 3);
  CHECK(servo.baud_bps() == 1'000'000);
  servo.device_write(item(servo, "return_delay_time"), 10);
  CHECK(servo.return_delay() == std::chrono::microseconds(20));
  servo.device_write(item(servo, "protocol_type"), 1);
  CHECK(servo.protocol() == wire::Protocol::V1);
}

TEST_CASE("The deferred items are ID, Baud Rate, Return Delay Time and the protocol item",
          "[model][servo]") {
  const Servo xm(test::shipped_model("xm430-w350"), 1);
  for (const char* key : {"id", "baud_rate", "return_delay_time", "protocol_type"}) {
    CAPTURE(key);
    CHECK(xm.defers(item(xm, key)));
  }
  for (const char* key : {"goal_position", "operating_mode", "torque_enable"}) {
    CAPTURE(key);
    CHECK_FALSE(xm.defers(item(xm, key)));
  }
  // MX-106(2.0) names address 13 Protocol Version.
  const Servo mx(test::shipped_model("mx-106-2"), 1);
  CHECK(mx.defers(item(mx, "protocol_version")));
}

TEST_CASE("A device write of a value that does not fit the item is refused and changes nothing",
          "[model][servo]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  const std::size_t id = item(servo, "id");
  CHECK_THROWS_AS(servo.device_write(id, 256), std::invalid_argument);
  CHECK_THROWS_AS(servo.device_write(id, -1), std::invalid_argument);
  CHECK(servo.table().get(id) == 1);
  CHECK(servo.id() == 1);
}

TEST_CASE("encoded gives an item's bytes little-endian, two's complement when signed",
          "[model][table]") {
  const Servo servo(test::shipped_model("xm430-w350"), 1);
  const model::ControlTable& table = servo.table();
  CHECK(table.encoded(item(servo, "goal_position"), 0x12345678) ==
        std::vector<std::uint8_t>{0x78, 0x56, 0x34, 0x12});
  CHECK(table.encoded(item(servo, "goal_velocity"), -2) ==
        std::vector<std::uint8_t>{0xFE, 0xFF, 0xFF, 0xFF});
  CHECK_THROWS_AS(table.encoded(item(servo, "id"), 300), std::invalid_argument);
  const model::ItemSpec& id = servo.spec().items[item(servo, "id")];
  CHECK(model::ControlTable::fits(id, 255));
  CHECK_FALSE(model::ControlTable::fits(id, 256));
}

TEST_CASE("raw_value reads bytes of the image as one little-endian number", "[model][table]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  servo.table().set("goal_position", 0x01020304);
  const std::size_t goal = servo.spec().items[item(servo, "goal_position")].address;
  CHECK(servo.table().raw_value(goal, 4) == 0x01020304);
  CHECK(servo.table().raw_value(goal + 1, 2) == 0x0203);
  const std::size_t size = servo.table().bytes().size();
  CHECK(servo.table().raw_value(size - 1, 1) == servo.table().bytes().back());
  CHECK_THROWS_AS(servo.table().raw_value(size - 1, 2), std::out_of_range);
  CHECK_THROWS_AS(servo.table().raw_value(0, 0), std::out_of_range);
  CHECK_THROWS_AS(servo.table().raw_value(0, 9), std::out_of_range);
}

TEST_CASE("The EEPROM change count moves with every changed EEPROM byte and nothing else",
          "[model][table]") {
  Servo servo(test::shipped_model("xm430-w350"), 1);
  model::ControlTable& table = servo.table();
  const std::uint64_t start = table.eeprom_changes();
  table.set("goal_position", 1000);  // RAM
  table.set("id", 1);                // EEPROM, unchanged
  CHECK(table.eeprom_changes() == start);
  table.set("id", 5);
  CHECK(table.eeprom_changes() == start + 1);
  const std::uint8_t mode_address = 11;
  const std::vector<std::uint8_t> velocity_mode = {1};
  REQUIRE(table.bus_write(mode_address, velocity_mode, wire::Protocol::V2).ok());
  CHECK(table.eeprom_changes() == start + 2);
  REQUIRE(table.bus_write(mode_address, velocity_mode, wire::Protocol::V2).ok());  // same value
  CHECK(table.eeprom_changes() == start + 2);
  const std::vector<std::uint8_t> image(table.bytes().begin(), table.bytes().end());
  table.set("id", 9);
  table.copy_from(item(servo, "id"), image);  // back to 5
  CHECK(table.get("id") == 5);
  CHECK(table.eeprom_changes() == start + 4);
  table.load_initial(true);  // a factory reset changes the ID and the mode back
  CHECK(table.eeprom_changes() == start + 6);
}
