// A servo speaking Modbus RTU across a restart (--state, docs/config.md "State file"): its
// Protocol Type 10 and its slave address come back, and it speaks Modbus again.
#include <catch2/catch.hpp>

#include "app/daemon/bus_state.hpp"
#include "app/daemon/state_keeper.hpp"
#include "bus/loopback_link.hpp"
#include "shipped_model.hpp"

namespace dxlemu::test::modbus_state {

TEST_CASE("A Modbus servo's state round-trips: Protocol Type 10 and its address come back",
          "[app][state][modbus]") {
  model::ControlTable table(test::shipped_model("ph42-020-s300-r"));
  table.set("protocol_type", wire::traits(wire::Protocol::Modbus).type_value);
  table.set("id", 247);
  table.set("homing_offset", -300);
  const app::BusState saved = {{"dxl0", {app::capture_state(table)}}};
  const std::string text = app::state_to_text(saved);
  CHECK(app::state_from_text(text, "state.json") == saved);

  // A fresh daemon whose config has the servo at its factory settings.
  sim::Scheduler scheduler;
  bus::LoopbackLink link;
  bus::Bus bus{scheduler, link};
  model::Servo& servo =
      bus.add_servo(std::make_unique<model::Servo>(test::shipped_model("ph42-020-s300-r"), 1));
  std::vector<std::string> writes;
  app::StateKeeper keeper("state.json", app::state_from_text(text, "state.json"),
                          [&](const std::filesystem::path&, std::string_view content) {
                            writes.emplace_back(content);
                          });
  keeper.add_port("dxl0", bus);
  keeper.restore();
  CHECK(servo.protocol() == wire::Protocol::Modbus);
  CHECK(servo.id() == 247);
  CHECK(servo.table().get("protocol_type") == 10);
  CHECK(servo.table().get("homing_offset") == -300);
  REQUIRE(writes.size() == 1);
  CHECK(app::state_from_text(writes.back(), "state.json") == saved);
}

}  // namespace dxlemu::test::modbus_state
