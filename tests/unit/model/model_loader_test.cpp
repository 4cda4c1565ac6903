// The model loader accepts the documented format and refuses anything else, naming the file, the
// JSON pointer and the reason (docs/model-format.md "Refusals").
#include <catch2/catch.hpp>

#include <algorithm>

#include "model/spec/firmware_variant.hpp"
#include "model/spec/model_loader.hpp"
#include "test_model.hpp"

using namespace dxlemu;
using nlohmann::json;

namespace {

// The error a modified test model raises, as "POINTER: REASON".
std::string refusal(const std::function<void(json&)>& change) {
  json j = test::test_model_json();
  change(j);
  try {
    model::model_from_json(j, "bad.json");
  } catch (const model::ModelError& e) {
    CHECK(e.origin() == "bad.json");
    CHECK(std::string(e.what()) ==
          "bad.json: " + (e.pointer().empty() ? std::string("/") : e.pointer()) + ": " +
              e.reason());
    return e.pointer() + ": " + e.reason();
  }
  return "accepted";
}

json& item(json& j, const std::string& key) {
  return test::item_json(j, key);
}

}  // namespace

TEST_CASE("A valid model file loads with every field", "[model][loader]") {
  const auto spec = test::test_model();
  CHECK(spec->name == "test-x");
  CHECK(spec->model_number == 4242);
  CHECK(spec->family == model::Family::X);
  CHECK(spec->protocols == std::vector{wire::Protocol::V2, wire::Protocol::V1});
  CHECK(spec->bps_for_index(1) == std::optional<std::uint32_t>(57600));
  CHECK(!spec->bps_for_index(2));
  CHECK(spec->table_size() == 60);
  CHECK(spec->items.size() == 21);
  const auto& goal_pwm = *spec->find("goal_pwm");
  CHECK(goal_pwm.is_signed);
  CHECK(goal_pwm.initial == 885);  // initial_from pwm_limit
  REQUIRE(goal_pwm.limit_min);
  CHECK(goal_pwm.limit_min->negate);
  CHECK(spec->items[goal_pwm.limit_min->item].key == "pwm_limit");
  CHECK(spec->find("model_number")->max == 65535);  // default: the whole width
  CHECK(spec->find("present_velocity")->min == -2147483648LL);
}

TEST_CASE("The motion figures load when present and stay empty when absent", "[model][loader]") {
  const auto bare = test::test_model();
  CHECK(bare->motion.degrees_per_pulse == 0.087890625);
  CHECK(bare->motion.velocity_unit_rpm == 0.229);
  CHECK(!bare->motion.current_unit_ma);
  CHECK(!bare->motion.no_load_speed_rpm);
  CHECK(!bare->motion.stall_torque_nm);
  CHECK(!bare->motion.nominal_voltage_v);
  CHECK(!bare->motion.stall_current_a);
  CHECK(!bare->motion.acceleration_unit_rpm2);

  json j = test::test_model_json();
  j["motion"]["current_unit_ma"] = 2.69;
  j["motion"]["no_load_speed_rpm"] = 46;
  j["motion"]["stall_torque_nm"] = 4.1;
  j["motion"]["nominal_voltage_v"] = 12.0;
  j["motion"]["stall_current_a"] = 2.3;
  j["motion"]["acceleration_unit_rpm2"] = 214.577;
  const auto spec = model::model_from_json(j, "motion.json");
  CHECK(spec.motion.current_unit_ma == std::optional(2.69));
  CHECK(spec.motion.no_load_speed_rpm == std::optional(46.0));
  CHECK(spec.motion.stall_torque_nm == std::optional(4.1));
  CHECK(spec.motion.nominal_voltage_v == std::optional(12.0));
  CHECK(spec.motion.stall_current_a == std::optional(2.3));
  CHECK(spec.motion.acceleration_unit_rpm2 == std::optional(214.577));
}

TEST_CASE("The loader refuses motion figures that are not positive numbers", "[model][loader]") {
  for (const char* key : {"nominal_voltage_v", "stall_current_a", "acceleration_unit_rpm2",
                          "no_load_speed_rpm", "stall_torque_nm", "current_unit_ma"}) {
    INFO(key);
    const std::string expected = std::string("/motion/") + key + ": must be a positive number";
    CHECK(refusal([key](json& j) { j["motion"][key] = 0; }) == expected);
    CHECK(refusal([key](json& j) { j["motion"][key] = -1.5; }) == expected);
    CHECK(refusal([key](json& j) { j["motion"][key] = "12"; }) == expected);
    CHECK(refusal([key](json& j) { j["motion"][key] = true; }) == expected);
    CHECK(refusal([key](json& j) { j["motion"][key] = nullptr; }) == expected);
  }
  CHECK(refusal([](json& j) { j["motion"]["stall_current_ma"] = 2300; }) ==
        "/motion/stall_current_ma: unknown field");
}

TEST_CASE("Items come out in address order whatever the file order", "[model][loader]") {
  json j = test::test_model_json();
  std::reverse(j["items"].begin(), j["items"].end());
  const auto spec = model::model_from_json(j, "reversed.json");
  for (std::size_t i = 1; i < spec.items.size(); ++i) {
    CHECK(spec.items[i - 1].address < spec.items[i].address);
  }
  CHECK(spec.items[spec.find("goal_position")->limit_max->item].key == "max_position_limit");
}

TEST_CASE("The loader refuses malformed JSON and missing or unknown fields", "[model][loader]") {
  CHECK_THROWS_WITH(model::parse_model("{\"name\": ", "broken.json"),
                    Catch::StartsWith("broken.json: /: not valid JSON"));
  CHECK(refusal([](json& j) { j.erase("model_number"); }) ==
        ": missing required field \"model_number\"");
  CHECK(refusal([](json& j) { j["model_number"] = "1020"; }) ==
        "/model_number: must be an integer");
  CHECK(refusal([](json& j) { j["model_number"] = 70000; }) ==
        "/model_number: must be between 0 and 65535, got 70000");
  CHECK(refusal([](json& j) { item(j, "id")["sise"] = 1; }) == "/items/1/sise: unknown field");
  CHECK(refusal([](json& j) { j["colour"] = "red"; }) == "/colour: unknown field");
}

TEST_CASE("The loader refuses a model without the items every servo needs", "[model][loader]") {
  for (const std::string key : {"id", "baud_rate", "return_delay_time"}) {
    CAPTURE(key);
    CHECK(refusal([&](json& j) {
            auto& items = j["items"];
            items.erase(std::find_if(items.begin(), items.end(),
                                     [&](const json& i) { return i["key"] == key; }));
          }) == "/items: has no item \"" + key +
                    "\" (every model needs id, baud_rate and return_delay_time; a FEETECH "
                    "model may lack return_delay_time)");
  }
}

TEST_CASE("The loader refuses an unknown family", "[model][loader]") {
  CHECK(refusal([](json& j) { j["family"] = "pro+"; }) ==
        "/family: unknown family \"pro+\" (known: x, mx2, mx1, ax, rx, ex, xl320, p, pro, dx, "
        "pro_a, y, sts, sms, scs, hls)");
}

TEST_CASE("The loader refuses an unsupported item size", "[model][loader]") {
  CHECK(refusal([](json& j) { item(j, "id")["size"] = 3; }) ==
        "/items/1/size: must be 1, 2 or 4, got 3");
}

TEST_CASE("The loader refuses overlapping items", "[model][loader]") {
  // PWM Limit is 2 bytes at 12; an item at 13 overlaps it.
  CHECK(refusal([](json& j) { item(j, "max_position_limit")["address"] = 13; }) ==
        "/items/4/address: overlaps /items/3 (\"pwm_limit\", addresses 12..13)");
}

TEST_CASE("The loader refuses a duplicate key or address", "[model][loader]") {
  CHECK(refusal([](json& j) { item(j, "operating_mode")["key"] = "id"; }) ==
        "/items/2/key: duplicate key \"id\" (also /items/1)");
  CHECK(refusal([](json& j) { item(j, "operating_mode")["address"] = 7; }) ==
        "/items/2/address: duplicate address 7 (also /items/1)");
}

TEST_CASE("The loader refuses an initial value outside the item's range", "[model][loader]") {
  CHECK(refusal([](json& j) { item(j, "id")["initial"] = 253; }) ==
        "/items/1/initial: value 253 is outside the item's range");
  CHECK(refusal([](json& j) { item(j, "operating_mode")["initial"] = 2; }) ==
        "/items/2/initial: value 2 is outside the item's range");
  CHECK(refusal([](json& j) { item(j, "id")["initial"] = 300; }) ==
        "/items/1/initial: must be between 0 and 255, got 300");
  CHECK(refusal([](json& j) { item(j, "pwm_limit")["initial"] = 900; }) ==
        "/items/3/initial: value 900 is outside the item's range");
}

TEST_CASE("The loader refuses a bound or initial_from naming an unknown item", "[model][loader]") {
  CHECK(refusal([](json& j) { item(j, "goal_position")["limit_max"] = "max_pos_limit"; }) ==
        "/items/8/limit_max: names an unknown item \"max_pos_limit\"");
  CHECK(refusal([](json& j) { item(j, "goal_pwm")["limit_min"] = "-pwm_limits"; }) ==
        "/items/7/limit_min: names an unknown item \"pwm_limits\"");
  CHECK(refusal([](json& j) { item(j, "goal_pwm")["initial_from"] = "nothing"; }) ==
        "/items/7/initial_from: names an unknown item \"nothing\"");
  CHECK(refusal([](json& j) { item(j, "goal_pwm")["initial"] = 0; }) ==
        "/items/7: needs exactly one of \"initial\" and \"initial_from\"");
}

TEST_CASE("The loader refuses a default baud index that is not in the table", "[model][loader]") {
  CHECK(refusal([](json& j) { j["default_baud_index"] = 2; }) ==
        "/default_baud_index: is not an index of baud_rates");
  CHECK(refusal([](json& j) { j["baud_rates"][1]["index"] = 0; }) ==
        "/baud_rates/1/index: lists index 0 twice");
}

TEST_CASE("The loader refuses an indirect block its items do not back", "[model][loader]") {
  CHECK(refusal([](json& j) { j["indirect"][0]["count"] = 5; }) ==
        "/indirect/0: entry 4 needs a 2-byte item at 48 and a 1-byte item at 54");
}

TEST_CASE("The loader refuses other malformed values", "[model][loader]") {
  CHECK(refusal([](json& j) { item(j, "id")["access"] = "W"; }) ==
        "/items/1/access: must be \"R\" or \"RW\", got \"W\"");
  CHECK(refusal([](json& j) { item(j, "id")["area"] = "ROM"; }) ==
        "/items/1/area: must be \"EEPROM\", \"RAM\" or \"Hybrid\", got \"ROM\"");
  CHECK(refusal([](json& j) { item(j, "id")["key"] = "Id"; }) ==
        "/items/1/key: must be snake_case (a-z, 0-9, _), got \"Id\"");
  CHECK(refusal([](json& j) {
          item(j, "id")["min"] = 10;
          item(j, "id")["max"] = 5;
        }) == "/items/1/max: is below min (10)");
  CHECK(refusal([](json& j) {
          j["protocols"] = json::array({2, 2});
        }) == "/protocols/1: lists a protocol twice");
  CHECK(refusal([](json& j) { j["motion"]["degrees_per_pulse"] = 0; }) ==
        "/motion/degrees_per_pulse: must be a positive number");
  CHECK(refusal([](json& j) { j["items"] = json::array(); }) ==
        "/items: must list at least one item");
}

TEST_CASE("An item absent in a protocol the model speaks loads with that protocol",
          "[model][loader]") {
  json j = test::test_model_json();
  j["protocols"] = json::array({2, "modbus"});
  item(j, "return_delay_time")["absent_in"] = json::array({"modbus"});
  const auto spec = model::model_from_json(j, "modbus.json");
  CHECK(spec.protocols == std::vector{wire::Protocol::V2, wire::Protocol::Modbus});
  const auto& delay = *spec.find("return_delay_time");
  CHECK(delay.absent_in == std::vector{wire::Protocol::Modbus});
  CHECK_FALSE(delay.present_in(wire::Protocol::Modbus));
  CHECK(delay.present_in(wire::Protocol::V2));
  CHECK(spec.find("id")->absent_in.empty());
  CHECK(spec.find("id")->present_in(wire::Protocol::Modbus));

  // Protocols with a number are written as that number, as in "protocols".
  json numbered = test::test_model_json();
  item(numbered, "return_delay_time")["absent_in"] = json::array({1});
  CHECK(model::model_from_json(numbered, "v1.json").find("return_delay_time")->absent_in ==
        std::vector{wire::Protocol::V1});
}

TEST_CASE("The loader refuses an absent_in that names a protocol the model does not speak",
          "[model][loader]") {
  const auto with_modbus = [](const json& absent_in) {
    return [absent_in](json& j) {
      j["protocols"] = json::array({2, "modbus"});
      item(j, "return_delay_time")["absent_in"] = absent_in;
    };
  };
  CHECK(refusal(with_modbus(json::array({"canbus"}))) ==
        "/items/20/absent_in/0: unknown protocol \"canbus\" (known: 1, 2, \"feetech\", "
        "\"modbus\")");
  CHECK(refusal(with_modbus(json::array({3}))) ==
        "/items/20/absent_in/0: must be between 1 and 2, got 3");
  CHECK(refusal(with_modbus(json::array({1}))) ==
        "/items/20/absent_in/0: names 1, which the model does not speak (its protocols: 2, "
        "\"modbus\")");
  CHECK(refusal(with_modbus(json::array({"modbus", "modbus"}))) ==
        "/items/20/absent_in/1: lists a protocol twice");
  CHECK(refusal(with_modbus(json::array())) ==
        "/items/20/absent_in: must list at least one protocol");
  CHECK(refusal(with_modbus(json::array({"modbus", 2}))) ==
        "/items/20/absent_in: names every protocol the model speaks: an item none of them "
        "reaches is no item");
  CHECK(refusal(with_modbus("modbus")) == "/items/20/absent_in: must be an array");
  // The test model speaks 2.0 and 1.0 only.
  CHECK(refusal([](json& j) { item(j, "return_delay_time")["absent_in"] = {"modbus"}; }) ==
        "/items/20/absent_in/0: names \"modbus\", which the model does not speak (its "
        "protocols: 2, 1)");
}

TEST_CASE("A firmware variant replaces the indirect blocks and rebuilds their items only",
          "[model][loader]") {
  json j = test::test_model_json();
  j["firmware_variants"] = json::parse(
      R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 44, "count": 2}],
           "notes": ["older"]}])");
  const auto base = model::model_from_json(j, "variant.json");
  REQUIRE(base.firmware_variants.size() == 1);
  CHECK(model::firmware_list(base) == std::to_string(base.firmware_version) + ", 7");
  CHECK_FALSE(model::model_for_firmware(base, 8).has_value());
  CHECK(model::model_for_firmware(base, base.firmware_version)->name == "test-x");
  const auto spec = *model::model_for_firmware(base, 7);
  CHECK(spec.name == "test-x@7");
  CHECK(spec.firmware_version == 7);
  CHECK(spec.firmware_variants.empty());
  CHECK(spec.notes.back() == "older");
  REQUIRE(spec.indirect.size() == 1);
  CHECK(spec.indirect[0].data == 44);
  CHECK(spec.items.size() == base.items.size() - 4);
  CHECK(spec.find("indirect_address_2")->address == 42);
  CHECK(spec.find("indirect_address_2")->initial == 45);  // its Data item, as in the model
  CHECK(spec.find("indirect_data_2")->address == 45);
  CHECK(spec.find("indirect_address_3") == nullptr);
  CHECK(spec.find("indirect_data_3") == nullptr);
  // Bounds still name the same items after the rebuild moved them.
  const auto& goal_pwm = *spec.find("goal_pwm");
  REQUIRE(goal_pwm.limit_min);
  CHECK(spec.items[goal_pwm.limit_min->item].key == "pwm_limit");
  CHECK(std::is_sorted(spec.items.begin(), spec.items.end(),
                       [](const auto& a, const auto& b) { return a.address < b.address; }));
}

TEST_CASE("The loader refuses a firmware variant that repeats a firmware or does not fit",
          "[model][loader]") {
  auto variant = [](const std::string& text) {
    return [text](json& j) { j["firmware_variants"] = json::parse(text); };
  };
  CHECK(refusal(variant(R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 44,
        "count": 2}], "notes": []}, {"firmware_version": 7, "indirect": [{"address": 40,
        "data": 44, "count": 1}], "notes": []}])")) ==
        "/firmware_variants/1/firmware_version: lists firmware 7 twice");
  CHECK(refusal(variant(R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 59,
        "count": 1}], "notes": []}])")) ==
        "/firmware_variants/0/indirect: item \"indirect_data_1\" at 59 overlaps "
        "\"present_temperature\" for firmware 7");
  CHECK(refusal([](json& j) {
          item(j, "goal_pwm")["limit_max"] = "indirect_address_3";
          j["firmware_variants"] = json::parse(
              R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 44, "count": 2}],
                   "notes": []}])");
        }) ==
        "/firmware_variants/0/indirect: \"goal_pwm\" names \"indirect_address_3\", which "
        "firmware 7 does not have");
  CHECK(refusal(variant(R"([{"firmware_version": 7, "indirect": [], "notes": []}])")) ==
        "/firmware_variants/0/indirect: must list at least one block");
  CHECK(refusal(variant(R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 44,
        "count": 1}]}])")) == "/firmware_variants/0: missing required field \"notes\"");
  CHECK(refusal([](json& j) {
          j.erase("indirect");
          j["firmware_variants"] = json::parse(
              R"([{"firmware_version": 7, "indirect": [{"address": 40, "data": 44, "count": 1}],
                   "notes": []}])");
        }) == "/firmware_variants/0: replaces indirect blocks, but the model has no \"indirect\"");
}
