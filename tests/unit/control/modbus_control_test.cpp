// The control API on a servo speaking Modbus RTU (docs/control-api.md "Modbus RTU servos"):
// list names the protocol, set and get work device-side, and servo.reboot and
// servo.factory_reset act although Modbus has no such instruction.
#include <catch2/catch.hpp>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "ports_target.hpp"

namespace dxlemu::test::modbus_control {

using nlohmann::json;

/// dxl0: a PH42-020-S300-R at ID 5 speaking Modbus RTU.
struct Rig : test::ApiRequests<Rig> {
  test::PortsTarget target;
  test::PortsTarget::Port& dxl0 = target.add_port("dxl0");
  model::Servo& ph = target.add(dxl0, "ph42-020-s300-r", 5);
  control::Api api{target};
  Rig() {
    ph.table().set("protocol_type", wire::traits(wire::Protocol::Modbus).type_value);
    ph.commit_deferred();
  }
};

TEST_CASE("list shows a Modbus servo's protocol as \"modbus\"; set and get work",
          "[control][modbus]") {
  Rig rig;
  const json listed = rig.result(R"({"cmd":"list"})");
  CHECK(listed["ports"][0]["servos"][0]["protocol"] == "modbus");
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":5,"item":"homing_offset","value":-7})") ==
        json::parse(R"({"item":"homing_offset","value":-7})"));
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":5,"item":"homing_offset"})")["value"] ==
        -7);
  // Back to 2.0 through the API: at once, as any protocol change made there.
  rig.result(R"({"cmd":"set","port":"dxl0","servo":5,"item":"protocol_type","value":2})");
  CHECK(rig.ph.protocol() == wire::Protocol::V2);
  CHECK(rig.result(R"({"cmd":"list"})")["ports"][0]["servos"][0]["protocol"] == 2);
}

TEST_CASE("servo.reboot and servo.factory_reset work on a Modbus servo, device-side",
          "[control][modbus]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":5,"item":"led_red","value":100})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":5,"item":"homing_offset","value":-7})");
  CHECK(rig.result(R"({"cmd":"servo.reboot","port":"dxl0","servo":5})") ==
        json::parse(R"({"servo":5,"attached":true,"booting":true})"));
  CHECK(rig.ph.table().get("led_red") == 0);           // RAM back to its initial values
  CHECK(rig.ph.table().get("homing_offset") == -7);    // EEPROM kept
  CHECK(rig.ph.protocol() == wire::Protocol::Modbus);  // Protocol Type is EEPROM
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  CHECK(rig.dxl0.link.deliveries().empty());  // nothing on the line
  // Factory Reset keeping the ID and baud: the model's 2.0 options apply; Protocol Type goes
  // back to 2 with the rest.
  CHECK(rig.result(R"({"cmd":"servo.factory_reset","port":"dxl0","servo":5,"keep":"id_baud"})") ==
        json::parse(R"({"servo":5,"attached":true,"booting":true})"));
  CHECK(rig.ph.table().get("homing_offset") == 0);
  CHECK(rig.ph.id() == 5);
  CHECK(rig.ph.protocol() == wire::Protocol::V2);
}

}  // namespace dxlemu::test::modbus_control
