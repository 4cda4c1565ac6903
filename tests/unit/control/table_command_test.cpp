// The control API's table command (docs/control-api.md "table"): every item of a servo's control
// table with its model-file facts and its value as get reads it, scaled by its unit.
#include <catch2/catch.hpp>

#include <string>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "ports_target.hpp"

using nlohmann::json;

namespace dxlemu::test::table_command {

/// dxl0: an XM430-W350 (ID 1) and an M54-40-S250-R (ID 2); dxl1: an STS3215 (ID 3).
struct Rig : ApiRequests<Rig> {
  PortsTarget target;
  PortsTarget::Port& dxl0 = target.add_port("dxl0");
  PortsTarget::Port& dxl1 = target.add_port("dxl1");
  model::Servo& xm = target.add(dxl0, "xm430-w350", 1);
  model::Servo& pro = target.add(dxl0, "m54-40-s250-r", 2);
  model::Servo& sts = target.add(dxl1, "feetech/sts3215", 3);
  control::Api api{target};

  /// The entry of item `key` in the table of servo `servo` on `port`.
  json item(const std::string& port, int servo, const std::string& key) {
    const json table =
        result(R"({"cmd":"table","port":")" + port + R"(","servo":)" + std::to_string(servo) + "}");
    for (const json& entry : table["items"]) {
      if (entry["key"] == key) {
        return entry;
      }
    }
    FAIL("no item " << key);
    return nullptr;
  }
};

TEST_CASE("table lists every item of the servo's model in address order, with its value",
          "[control][table]") {
  Rig rig;
  const json table = rig.result(R"({"cmd":"table","port":"dxl0","servo":1})");
  CHECK(table["port"] == "dxl0");
  CHECK(table["servo"] == 1);
  CHECK(table["model"] == "xm430-w350");
  CHECK(table["protocol"] == 2);
  REQUIRE(table["items"].size() == rig.xm.spec().items.size());
  for (std::size_t i = 0; i < rig.xm.spec().items.size(); ++i) {
    CAPTURE(i);
    CHECK(table["items"][i]["key"] == rig.xm.spec().items[i].key);
    CHECK(table["items"][i]["value"] == rig.xm.table().get(i));
  }
  // The FEETECH servo names its protocol as list does.
  CHECK(rig.result(R"({"cmd":"table","port":"dxl1","servo":3})")["protocol"] == "feetech");
}

TEST_CASE("A table item carries its model-file facts, and its value scaled by its unit",
          "[control][table]") {
  Rig rig;
  CHECK(rig.item("dxl0", 1, "goal_position") ==
        json::parse(R"({"key":"goal_position","name":"Goal Position","address":116,"size":4,)"
                    R"("access":"RW","area":"RAM","min":0,"max":4095,"unit":"1 [pulse]",)"
                    R"("value":2048,"scaled":2048,"scaled_unit":"pulse"})"));
  // Read-only, EEPROM, no unit: neither unit nor scaled.
  CHECK(rig.item("dxl0", 1, "model_number") ==
        json::parse(R"({"key":"model_number","name":"Model Number","address":0,"size":2,)"
                    R"("access":"R","area":"EEPROM","min":0,"max":65535,"value":1020})"));
  // The only accepted values, when the model lists them.
  CHECK(rig.item("dxl0", 1, "operating_mode")["values"] == json::parse("[0,1,3,4,5,16]"));
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"present_velocity","value":-100})");
  const json velocity = rig.item("dxl0", 1, "present_velocity");
  CHECK(velocity["value"] == -100);
  CHECK(velocity["unit"] == "0.229 [rev/min]");
  CHECK(velocity["scaled"] == -22.9);
  CHECK(velocity["scaled_unit"] == "rev/min");
  // A unit that says more than a factor, or a malformed one, is shown but not scaled.
  const json acceleration = rig.item("dxl0", 1, "profile_acceleration");
  CHECK(acceleration["unit"] == "214.577 [rev/min²] / 1 [ms]");
  CHECK_FALSE(acceleration.contains("scaled"));
  CHECK_FALSE(acceleration.contains("scaled_unit"));
  const json torque_limit = rig.item("dxl0", 2, "torque_limit");
  CHECK(torque_limit["unit"] == "16.11328 mA]");
  CHECK_FALSE(torque_limit.contains("scaled"));
}

TEST_CASE("table reads the values get reads, after set", "[control][table]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl1","servo":3,"item":"goal_position","value":1000})");
  const json goal = rig.item("dxl1", 3, "goal_position");
  CHECK(goal["value"] ==
        rig.result(R"({"cmd":"get","port":"dxl1","servo":3,"item":"goal_position"})")["value"]);
  CHECK(goal["value"] == 1000);
}

TEST_CASE("table refuses what get refuses, with the same messages", "[control][table]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"table","port":"dxl0","servo":9})") ==
        rig.error(R"({"cmd":"get","port":"dxl0","servo":9,"item":"id"})"));
  CHECK(rig.error(R"({"cmd":"table","port":"dxl0","servo":9})") ==
        "no servo 9 on dxl0 (servos: 1, 2)");
  CHECK(rig.error(R"({"cmd":"table","port":"dxl9","servo":1})") ==
        "port \"dxl9\" does not exist (ports: dxl0, dxl1)");
  CHECK(rig.error(R"({"cmd":"table","servo":1})") ==
        "\"port\" is required: there are 2 ports (dxl0, dxl1)");
  CHECK(rig.error(R"({"cmd":"table","port":"dxl0"})") == "\"servo\" is required");
  CHECK(rig.error(R"({"cmd":"table","port":"dxl0","servo":1,"item":"id"})") ==
        "unknown field \"item\" for table (it takes port, servo)");
}

}  // namespace dxlemu::test::table_command
