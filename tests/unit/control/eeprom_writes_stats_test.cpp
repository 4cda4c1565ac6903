// stats' eeprom_writes (docs/control-api.md "stats"): per port, servo ID → EEPROM item → how many
// bus instructions wrote it; the control API's own set is not counted.
#include <catch2/catch.hpp>

#include <chrono>
#include <string>

#include "api_requests.hpp"
#include "bus/bus_rig.hpp"
#include "control/api.hpp"
#include "ports_target.hpp"
#include "wire/instruction_encoder.hpp"

using nlohmann::json;
using namespace std::chrono_literals;

namespace dxlemu::test::eeprom_writes_stats {

/// dxl0: two XM430-W350 (IDs 1 and 2); dxl1: one AX-12A (ID 3).
struct Rig : ApiRequests<Rig> {
  PortsTarget target;
  PortsTarget::Port& dxl0 = target.add_port("dxl0");
  PortsTarget::Port& dxl1 = target.add_port("dxl1");
  model::Servo& xm1 = target.add(dxl0, "xm430-w350", 1);
  model::Servo& xm2 = target.add(dxl0, "xm430-w350", 2);
  model::Servo& ax3 = target.add(dxl1, "ax-12a", 3);
  control::Api api{target};

  /// Sends `packet` to dxl0 and lets its replies go out.
  void send(wire::Instruction instruction, std::uint8_t id = 1) {
    const auto bytes = wire::encode_instruction({wire::Protocol::V2, id, std::move(instruction)});
    dxl0.bus.receive(bytes, target.now(), BusRig::kBaud);
    target.scheduler.advance_by(10ms);
  }
};

TEST_CASE("stats counts the EEPROM items bus instructions wrote, per servo ID",
          "[control][eeprom_writes]") {
  Rig rig;
  CHECK(rig.result(R"({"cmd":"stats"})")["dxl0"]["eeprom_writes"] == json::object());
  rig.send(wire::Write{9, {3}});             // Return Delay Time of servo 1
  rig.send(wire::Write{116, {0, 4, 0, 0}});  // Goal Position: RAM, not counted
  rig.send(wire::SyncWrite{9, 1, {{1, {4}}, {2, {5}}}}, wire::kBroadcastId);
  rig.send(wire::Write{64, {1}});  // Torque Enable on: EEPROM locked
  rig.send(wire::Write{9, {6}});   // refused with an Access Error: not counted
  // The control API's set is a device-side change, not a bus write.
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"return_delay_time","value":7})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"id","value":2})");
  CHECK(rig.xm1.table().get("return_delay_time") == 4);
  CHECK(rig.xm2.table().get("return_delay_time") == 7);
  const json stats = rig.result(R"({"cmd":"stats"})");
  CHECK(stats["dxl0"]["eeprom_writes"] ==
        json::parse(R"({"1":{"return_delay_time":2},"2":{"return_delay_time":1}})"));
  CHECK(stats["dxl1"]["eeprom_writes"] == json::object());
  CHECK(rig.result(R"({"cmd":"stats","port":"dxl0"})")["dxl0"]["eeprom_writes"] ==
        stats["dxl0"]["eeprom_writes"]);
}

TEST_CASE("eeprom_writes follows a servo's new ID and names each item written",
          "[control][eeprom_writes]") {
  Rig rig;
  rig.send(wire::Write{7, {9}});                                 // ID 1 → 9, after the status
  rig.send(wire::Write{48, {0xFF, 0x0F, 0, 0, 0, 0, 0, 0}}, 9);  // Max and Min Position Limit
  CHECK(rig.result(R"({"cmd":"stats","port":"dxl0"})")["dxl0"]["eeprom_writes"] ==
        json::parse(R"({"9":{"id":1,"max_position_limit":1,"min_position_limit":1}})"));
}

}  // namespace dxlemu::test::eeprom_writes_stats
