// make_servo: a servo of a bus config with its item overrides, EEPROM ones kept over power cycles
// (docs/config.md).
#include <catch2/catch.hpp>

#include "app/config/make_servo.hpp"
#include "shipped_models.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;

TEST_CASE("make_servo builds the model at its ID with the config's item overrides",
          "[app][config]") {
  const auto servo = app::make_servo(
      test::shipped_models(), {"xm430-w350", 7, {{"return_delay_time", 0}, {"led", 1}}}, 1ms);
  CHECK(servo->spec().name == "xm430-w350");
  CHECK(servo->id() == 7);
  CHECK(servo->table().get("return_delay_time") == 0);
  CHECK(servo->table().get("led") == 1);
  // Untouched items keep their model's initial values.
  CHECK(servo->table().get("secondary_id") == 255);
}

TEST_CASE(
    "An EEPROM override survives a reboot even behind a FEETECH Lock flag of 1, a RAM "
    "override does not",
    "[app][config]") {
  // The STS3215's Lock flag starts at 1: a bus write to EEPROM would be lost on power-off.
  const auto servo = app::make_servo(
      test::shipped_models(), {"sts3215", 1, {{"return_delay_time", 5}, {"acceleration", 9}}}, 1ms);
  REQUIRE(servo->table().get("lock_flag") == 1);
  const std::size_t delay = servo->table().index("return_delay_time");
  CHECK(servo->table().kept_value(delay) == 5);
  CHECK(servo->table().get("acceleration") == 9);
  servo->reboot();
  CHECK(servo->table().get("return_delay_time") == 5);
  CHECK(servo->table().get("acceleration") == 0);
}
