// StateKeeper (docs/config.md "State file"): what it restores at start, and that it writes the
// file again exactly when non-volatile memory changed.
#include <catch2/catch.hpp>

#include "app/daemon/state_keeper.hpp"
#include "bus/loopback_link.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;

namespace {

// One port "dxl0" with a bus whose state a keeper keeps; every write is recorded.
struct KeeperRig {
  sim::Scheduler scheduler;
  bus::LoopbackLink link;
  bus::Bus bus{scheduler, link};
  std::vector<std::string> writes;

  model::Servo& add(const std::string& name, std::uint8_t id) {
    return bus.add_servo(std::make_unique<model::Servo>(test::shipped_model(name), id));
  }
  app::StateKeeper keeper(std::optional<std::filesystem::path> file, app::BusState saved = {}) {
    app::StateKeeper made(std::move(file), std::move(saved),
                          [this](const std::filesystem::path& path, std::string_view content) {
                            CHECK(path == "state.json");
                            writes.emplace_back(content);
                          });
    made.add_port("dxl0", bus);
    return made;
  }
  // The servos of "dxl0" in the last write.
  std::vector<app::ServoState> written() const {
    REQUIRE(!writes.empty());
    return app::state_from_text(writes.back(), "state.json").at("dxl0");
  }
};

// The value of `key` in `state`.
std::int64_t kept(const app::ServoState& state, const std::string& key) {
  for (const auto& [item, value] : state.eeprom) {
    if (item == key) {
      return value;
    }
  }
  FAIL("no item " << key);
  return 0;
}

}  // namespace

TEST_CASE("A saved servo of the same model gets its EEPROM back, and its saved ID applies",
          "[app][state]") {
  KeeperRig rig;
  model::Servo& servo = rig.add("xm430-w350", 1);
  model::ControlTable saved_table(test::shipped_model("xm430-w350"));
  saved_table.set("id", 9);
  saved_table.set("return_delay_time", 0);
  auto keeper = rig.keeper("state.json", {{"dxl0", {app::capture_state(saved_table)}}});
  keeper.restore();
  CHECK(servo.id() == 9);
  CHECK(servo.table().get("return_delay_time") == 0);
  // The restored state is written at once, so the file says what runs.
  REQUIRE(rig.writes.size() == 1);
  CHECK(rig.written() == std::vector<app::ServoState>{app::capture_state(saved_table)});
}

TEST_CASE("A saved servo of another model is left at its config", "[app][state]") {
  KeeperRig rig;
  model::Servo& servo = rig.add("xm430-w350", 1);
  model::ControlTable other(test::shipped_model("ax-12a"));
  other.set("id", 9);
  auto keeper = rig.keeper("state.json", {{"dxl0", {app::capture_state(other)}}});
  keeper.restore();
  CHECK(servo.id() == 1);
  CHECK(rig.written().front().model == "xm430-w350");
}

TEST_CASE("The state file is written again only when an EEPROM byte changed", "[app][state]") {
  KeeperRig rig;
  model::Servo& servo = rig.add("xm430-w350", 1);
  auto keeper = rig.keeper("state.json");
  keeper.restore();
  REQUIRE(rig.writes.size() == 1);
  keeper.save_if_changed();
  servo.table().set("goal_position", 1000);  // RAM
  keeper.save_if_changed();
  CHECK(rig.writes.size() == 1);
  servo.table().set("return_delay_time", 7);
  keeper.save_if_changed();
  REQUIRE(rig.writes.size() == 2);
  CHECK(kept(rig.written().front(), "return_delay_time") == 7);
  // Changed and changed back between two looks: the same bytes, nothing to write.
  servo.table().set("return_delay_time", 3);
  servo.table().set("return_delay_time", 7);
  keeper.save_if_changed();
  CHECK(rig.writes.size() == 2);
}

TEST_CASE("Without a state file the keeper only commits the servos' settings", "[app][state]") {
  KeeperRig rig;
  model::Servo& servo = rig.add("xm430-w350", 1);
  auto keeper = rig.keeper(std::nullopt);
  // An ID written device-side waits for commit_deferred, as one from a config does.
  servo.table().set("id", 4);
  keeper.restore();
  CHECK(servo.id() == 4);
  servo.table().set("return_delay_time", 7);
  keeper.save_if_changed();
  CHECK(rig.writes.empty());
}
