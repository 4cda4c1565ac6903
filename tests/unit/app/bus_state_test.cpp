// State files (docs/config.md "State file"): the writable EEPROM items of every servo, restored
// at the next start; a broken file is refused naming the pointer.
#include <catch2/catch.hpp>

#include <algorithm>

#include "app/config/bus_config.hpp"
#include "app/daemon/bus_state.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;

namespace {

std::string state_refusal(const std::string& text) {
  try {
    app::state_from_text(text, "state.json");
  } catch (const app::ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("A state keeps the writable EEPROM items and survives its own text", "[app][state]") {
  model::ControlTable table(test::shipped_model("xm430-w350"));
  table.set("id", 9);
  table.set("return_delay_time", 0);
  table.set("goal_position", 1000);  // RAM: not kept
  const app::ServoState state = app::capture_state(table);
  CHECK(state.model == "xm430-w350");
  const auto has = [&](const std::string& key) {
    return std::any_of(state.eeprom.begin(), state.eeprom.end(),
                       [&](const auto& item) { return item.first == key; });
  };
  CHECK(has("id"));
  CHECK(has("baud_rate"));
  CHECK(has("return_delay_time"));
  CHECK(!has("model_number"));   // read-only
  CHECK(!has("goal_position"));  // RAM
  const app::BusState bus = {{"dxl0", {state}}, {"arm", {}}};
  CHECK(app::state_from_text(app::state_to_text(bus), "state.json") == bus);

  model::ControlTable fresh(test::shipped_model("xm430-w350"));
  app::restore_state(fresh, state, "state.json", "/ports/dxl0/0");
  CHECK(fresh.get("id") == 9);
  CHECK(fresh.get("return_delay_time") == 0);
  CHECK(fresh.get("goal_position") != 1000);
  CHECK(app::eeprom_image(fresh) == app::eeprom_image(table));
}

TEST_CASE("The EEPROM image changes with EEPROM items only", "[app][state]") {
  model::ControlTable table(test::shipped_model("ax-12a"));
  const auto before = app::eeprom_image(table);
  table.set("goal_position", 100);
  CHECK(app::eeprom_image(table) == before);
  table.set("cw_angle_limit", 100);
  CHECK(app::eeprom_image(table) != before);
}

TEST_CASE("A state keeps the saved values of the Hybrid items, not the unsaved ones",
          "[app][state][y]") {
  model::ControlTable table(test::shipped_model("ym070-210-r051-rh"));
  const std::int64_t factory = table.get("position_p_gain");
  const auto kept = [](const app::ServoState& state, const std::string& key) {
    const auto it = std::find_if(state.eeprom.begin(), state.eeprom.end(),
                                 [&](const auto& item) { return item.first == key; });
    REQUIRE(it != state.eeprom.end());
    return it->second;
  };
  const auto before = app::eeprom_image(table);
  const auto changes = table.eeprom_changes();
  table.set("position_p_gain", 5000000);  // written, not saved: lost at power-off
  CHECK(kept(app::capture_state(table), "position_p_gain") == factory);
  CHECK(app::eeprom_image(table) == before);
  table.save_hybrid();  // Hybrid Save(170) = 1
  CHECK(table.eeprom_changes() != changes);
  CHECK(app::eeprom_image(table) != before);
  const app::ServoState state = app::capture_state(table);
  CHECK(kept(state, "position_p_gain") == 5000000);

  model::ControlTable fresh(test::shipped_model("ym070-210-r051-rh"));
  app::restore_state(fresh, state, "state.json", "/ports/dxl0/0");
  CHECK(fresh.get("position_p_gain") == 5000000);
  fresh.load_initial(false);  // a reboot restores the saved value
  CHECK(fresh.get("position_p_gain") == 5000000);
  CHECK(app::eeprom_image(fresh) == app::eeprom_image(table));
}

TEST_CASE("A state item the model cannot take is refused before anything is restored",
          "[app][state]") {
  model::ControlTable table(test::shipped_model("xm430-w350"));
  const auto refuse = [&](const app::ServoState& state) -> std::string {
    try {
      app::restore_state(table, state, "state.json", "/ports/dxl0/0");
    } catch (const app::ConfigError& e) {
      return e.what();
    }
    return "accepted";
  };
  CHECK(refuse({"xm430-w350", {{"id", 5}, {"speed", 1}}}) ==
        "state.json: /ports/dxl0/0/eeprom/speed: xm430-w350 has no item \"speed\"");
  CHECK(refuse({"xm430-w350", {{"id", 5}, {"goal_position", 1}}}) ==
        "state.json: /ports/dxl0/0/eeprom/goal_position: is not a writable EEPROM item");
  CHECK(refuse({"xm430-w350", {{"id", 5}, {"return_delay_time", 255}}}) ==
        "state.json: /ports/dxl0/0/eeprom/return_delay_time: 255 is outside the item's range 0 "
        "~ 254");
  CHECK(table.get("id") == 1);  // nothing was set
}

TEST_CASE("A broken state file is refused naming the pointer and the reason", "[app][state]") {
  CHECK_THAT(state_refusal("{\"format\""), Catch::StartsWith("state.json: /: not valid JSON"));
  // A number too large for a double is nlohmann's out_of_range, not a parse_error.
  CHECK_THAT(state_refusal(R"({"format": "dxlemu-state", "version": 1e999, "ports": {}})"),
             Catch::StartsWith("state.json: /: not valid JSON"));
  CHECK(state_refusal(R"({"format": "x", "version": 1, "ports": {}})") ==
        "state.json: /format: must be \"dxlemu-state\" (is this a dxlemu state file?)");
  CHECK(state_refusal(R"({"format": "dxlemu-state", "version": 2, "ports": {}})") ==
        "state.json: /version: must be 1");
  CHECK(state_refusal(R"({"format": "dxlemu-state", "version": 1, "ports": []})") ==
        "state.json: /ports: must be an object of port names");
  CHECK(state_refusal(
            R"({"format": "dxlemu-state", "version": 1, "ports": {"a": [{"eeprom": {}}]}})") ==
        "state.json: /ports/a/0/model: must be a string");
  CHECK(state_refusal(
            R"({"format": "dxlemu-state", "version": 1, "ports": {"a": [{"model": "m"}]}})") ==
        "state.json: /ports/a/0/eeprom: must be an object of item keys and values");
  CHECK(state_refusal(R"({"format": "dxlemu-state", "version": 1,
                    "ports": {"a": [{"model": "m", "eeprom": {"id": "1"}}]}})") ==
        "state.json: /ports/a/0/eeprom/id: must be an integer");
  CHECK(app::state_from_text(R"({"format": "dxlemu-state", "version": 1, "ports": {}})", "s")
            .empty());
}

TEST_CASE("An absent state file is an empty state: the first run starts from the config",
          "[app][state]") {
  CHECK(app::read_state("/nonexistent/state.json").empty());
}
