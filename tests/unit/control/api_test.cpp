// The control API (docs/control-api.md): JSON requests in, JSON replies out, no I/O. Every
// command's success reply and every kind of malformed request, on real servos and a hand-stepped
// clock.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "api_requests.hpp"
#include "bus/bus.hpp"
#include "bus/bus_rig.hpp"
#include "bus/loopback_link.hpp"
#include "control/api.hpp"
#include "control/target.hpp"
#include "ports_target.hpp"
#include "wire/instruction_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using nlohmann::json;

namespace {

using FakeTarget = test::PortsTarget;

/// dxl0: two XM430-W350 (IDs 1 and 2); dxl1: one AX-12A (ID 3).
struct Rig : test::ApiRequests<Rig> {
  FakeTarget target;
  FakeTarget::Port& dxl0 = target.add_port("dxl0");
  FakeTarget::Port& dxl1 = target.add_port("dxl1");
  model::Servo& xm1 = target.add(dxl0, "xm430-w350", 1);
  model::Servo& xm2 = target.add(dxl0, "xm430-w350", 2);
  model::Servo& ax3 = target.add(dxl1, "ax-12a", 3);
  control::Api api{target};
};

}  // namespace

// --- success replies -----------------------------------------------------------------------------

TEST_CASE("list shows every port with its facts and the key state of each servo", "[control]") {
  Rig rig;
  CHECK(
      rig.api.handle(R"({"id":1,"cmd":"list"})") ==
      R"({"id":1,"ok":true,"result":{"ports":[)"
      R"({"name":"dxl0","pty":"/dev/pts/dxl0","servos":[)"
      R"({"id":1,"model":"xm430-w350","protocol":2,"baud":57600,"firmware_version":45,)"
      R"("torque":false,"present_position":2048,"present_temperature":25,)"
      R"("present_input_voltage":127,"hardware_error_status":0,"moving":false,"attached":true},)"
      R"({"id":2,"model":"xm430-w350","protocol":2,"baud":57600,"firmware_version":45,)"
      R"("torque":false,"present_position":2048,"present_temperature":25,)"
      R"("present_input_voltage":127,"hardware_error_status":0,"moving":false,"attached":true}]},)"
      R"({"name":"dxl1","pty":"/dev/pts/dxl1","servos":[)"
      R"({"id":3,"model":"ax-12a","protocol":1,"baud":1000000,"firmware_version":1,)"
      R"("torque":false,"present_position":512,"present_temperature":25,)"
      R"("present_input_voltage":100,"moving":false,"attached":true}]}]}})");
}

TEST_CASE("get reads an item by key, or an address range as little-endian bytes", "[control]") {
  Rig rig;
  rig.xm1.table().set("present_position", 0x12345);
  CHECK(rig.api.handle(
            R"({"id":2,"cmd":"get","port":"dxl0","servo":1,"item":"present_temperature"})") ==
        R"({"id":2,"ok":true,"result":{"item":"present_temperature","value":25}})");
  CHECK(rig.api.handle(R"({"id":3,"cmd":"get","port":"dxl0","servo":1,"address":132,"size":4})") ==
        R"({"id":3,"ok":true,"result":{"address":132,"size":4,"value":74565,)"
        R"("bytes":[69,35,1,0]}})");
  // Any range within the table, even across items and reserved bytes.
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"address":0,"size":2})") ==
        json::parse(R"({"address":0,"size":2,"value":1020,"bytes":[252,3]})"));
  // A signed item reads signed by key.
  rig.xm1.table().set("present_current", -5);
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_current"})")["value"] ==
        -5);
}

TEST_CASE("set of a Present value moves what get reads and the shaft stays there", "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":4,"cmd":"set","port":"dxl0","servo":1,)"
                       R"("item":"present_position","value":1000})") ==
        R"({"id":4,"ok":true,"result":{"item":"present_position","value":1000}})");
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_position"})")["value"] ==
        1000);
  // The motion model took it as where the shaft is: ticks keep it there.
  rig.result(R"({"cmd":"clock.step","ms":50})");
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_position"})")["value"] ==
        1000);
  CHECK(rig.xm2.table().get("present_position") == 2048);  // the other servo is untouched
}

TEST_CASE("A value set through the API is what a bus Read returns", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"present_temperature","value":70})");
  const auto read = wire::encode_instruction({wire::Protocol::V2, 2, wire::Read{146, 1}});
  rig.dxl0.bus.receive(read, rig.target.now(), test::BusRig::kBaud);
  rig.result(R"({"cmd":"clock.step","ms":10})");
  REQUIRE(rig.dxl0.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.dxl0.link.deliveries()[0].bytes) == "id=2 error=0x00 params=46");
}

TEST_CASE("set by address and size needs the range to be exactly one item", "[control]") {
  Rig rig;
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"address":146,"size":1,"value":60})") ==
        json::parse(R"({"item":"present_temperature","value":60})"));
  CHECK(rig.xm1.table().get("present_temperature") == 60);
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"address":132,"size":2,"value":1})") ==
        "address 132 size 2 is not exactly one item of xm430-w350: present_position at 132 is 4 "
        "bytes");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"address":133,"size":1,"value":1})") ==
        "address 133 size 1 is not exactly one item of xm430-w350");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"address":14,"size":1,"value":1})") ==
        "address 14 size 1 is not exactly one item of xm430-w350");
  CHECK(rig.xm1.table().get("present_position") == 2048);
}

TEST_CASE("set bypasses the bus's access rules: read-only, EEPROM locked, out of range",
          "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"torque_enable","value":1})");
  // EEPROM is locked while torque is on; the API writes it anyway.
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"temperature_limit",)"
                   R"("value":60})")["value"] == 60);
  // Beyond the item's range (Max Position Limit 4095) but within its 4 bytes.
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"max_position_limit",)"
                   R"("value":100000})")["value"] == 100000);
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"model_number",)"
                   R"("value":1})")["value"] == 1);
}

TEST_CASE("set of a goal with torque on moves the servo on a stepped clock", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"torque_enable","value":1})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"goal_position","value":3000})");
  rig.result(R"({"cmd":"clock.step","ms":2000})");
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_position"})")["value"] ==
        3000);
  const json listed = rig.result(R"({"cmd":"list"})");
  CHECK(listed["ports"][0]["servos"][0]["torque"] == true);
  CHECK(listed["ports"][0]["servos"][0]["moving"] == false);
}

TEST_CASE("set of the ID, baud rate or protocol takes effect on the bus at once", "[control]") {
  Rig rig;
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"id","value":7})") ==
        json::parse(R"({"item":"id","value":7})"));
  CHECK(rig.xm1.id() == 7);
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":7,"item":"id"})")["value"] == 7);
  rig.result(R"({"cmd":"set","port":"dxl0","servo":7,"item":"baud_rate","value":3})");
  CHECK(rig.xm1.baud_bps() == 1000000);
  rig.result(R"({"cmd":"set","port":"dxl0","servo":7,"item":"protocol_type","value":1})");
  CHECK(rig.xm1.protocol() == wire::Protocol::V1);
  rig.result(R"({"cmd":"set","port":"dxl0","servo":7,"item":"return_delay_time","value":0})");
  CHECK(rig.xm1.return_delay() == sim::SimDuration{0});
}

TEST_CASE("condition.set changes one servo's conditions and the supply reaches the table",
          "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":5,"cmd":"condition.set","port":"dxl0","servo":2,)"
                       R"("ambient_temperature":40,"supply_voltage":11.1,"blocked":true})") ==
        R"({"id":5,"ok":true,"result":{"ambient_temperature":40.0,"supply_voltage":11.1,)"
        R"("external_load":0.0,"blocked":true}})");
  const model::Conditions& c = rig.xm2.motion().conditions();
  CHECK(c.ambient_c == 40);
  CHECK(c.supply_v == 11.1);
  CHECK(c.blocked);
  CHECK(rig.xm1.motion().conditions().supply_v == 12.7);  // the other servo keeps its own
  // The table shows the new supply from the next motion tick.
  CHECK(rig.xm2.table().get("present_input_voltage") == 127);
  rig.result(R"({"cmd":"clock.step","ms":1})");
  CHECK(rig.result(
            R"({"cmd":"get","port":"dxl0","servo":2,"item":"present_input_voltage"})")["value"] ==
        111);
  // A later change keeps what it does not name.
  CHECK(rig.result(R"({"cmd":"condition.set","port":"dxl0","servo":2,"external_load":-0.5})") ==
        json::parse(R"({"ambient_temperature":40.0,"supply_voltage":11.1,"external_load":-0.5,)"
                    R"("blocked":true})"));
}

TEST_CASE("condition.set without a servo applies to every servo of the port", "[control]") {
  Rig rig;
  const double ax_supply = rig.ax3.motion().conditions().supply_v;
  CHECK(rig.result(R"({"cmd":"condition.set","port":"dxl0","supply_voltage":10})") ==
        json::parse(R"([{"id":1,"ambient_temperature":25.0,"supply_voltage":10.0,)"
                    R"("external_load":0.0,"blocked":false},)"
                    R"({"id":2,"ambient_temperature":25.0,"supply_voltage":10.0,)"
                    R"("external_load":0.0,"blocked":false}])"));
  CHECK(rig.xm1.motion().conditions().supply_v == 10);
  CHECK(rig.xm2.motion().conditions().supply_v == 10);
  CHECK(rig.ax3.motion().conditions().supply_v == ax_supply);  // another port
  rig.result(R"({"cmd":"condition.set","port":"dxl1","supply_voltage":9.5})");
  rig.result(R"({"cmd":"clock.step","ms":1})");
  CHECK(rig.result(R"({"cmd":"get","port":"dxl1","servo":3,"item":"present_voltage"})")["value"] ==
        95);
}

TEST_CASE("clock.now reports simulated time in nanoseconds and milliseconds, and the timing",
          "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":6,"cmd":"clock.now"})") ==
        R"({"id":6,"ok":true,"result":{"ns":0,"ms":0.0,"timing":"manual"}})");
  rig.target.scheduler.advance_by(1500us);
  CHECK(rig.result(R"({"cmd":"clock.now"})") ==
        json::parse(R"({"ns":1500000,"ms":1.5,"timing":"manual"})"));
  rig.target.manual = false;
  CHECK(rig.result(R"({"cmd":"clock.now"})")["timing"] == "realtime");
}

TEST_CASE("clock.step advances simulated time by ms, us or ns and runs what is due", "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":7,"cmd":"clock.step","ms":10})") ==
        R"({"id":7,"ok":true,"result":{"ns":10000000,"ms":10.0}})");
  CHECK(rig.result(R"({"cmd":"clock.step","us":2.5})") ==
        json::parse(R"({"ns":10002500,"ms":10.0025})"));
  CHECK(rig.result(R"({"cmd":"clock.step","ns":1})")["ns"] == 10002501);
  // A Ping's status is due after its modelled delays: only a step delivers it.
  const auto ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  rig.dxl0.bus.receive(ping, rig.target.now(), test::BusRig::kBaud);
  CHECK(rig.dxl0.link.deliveries().empty());
  rig.result(R"({"cmd":"clock.step","ms":10})");
  CHECK(rig.dxl0.link.deliveries().size() == 1);
}

TEST_CASE("stats reports every counter of every port, or of the one asked for", "[control]") {
  Rig rig;
  const auto ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  rig.dxl0.bus.receive(ping, rig.target.now(), test::BusRig::kBaud);
  rig.target.scheduler.advance_by(10ms);
  const std::string dxl0 =
      R"("dxl0":{"bytes_in":10,"frames":1,"garbage_bytes":0,"bad_checks":0,"truncated":0,)"
      R"("impossible_lengths":0,"decode_errors":0,"replies":1,"unread_drops":0,"collisions":0,)"
      R"("id_conflicts":0,"faults_injected":0,"eeprom_writes":{}})";
  const std::string dxl1 =
      R"("dxl1":{"bytes_in":0,"frames":0,"garbage_bytes":0,"bad_checks":0,"truncated":0,)"
      R"("impossible_lengths":0,"decode_errors":0,"replies":0,"unread_drops":0,"collisions":0,)"
      R"("id_conflicts":0,"faults_injected":0,"eeprom_writes":{}})";
  CHECK(rig.api.handle(R"({"id":8,"cmd":"stats"})") ==
        R"({"id":8,"ok":true,"result":{)" + dxl0 + "," + dxl1 + "}}");
  CHECK(rig.api.handle(R"({"id":9,"cmd":"stats","port":"dxl1"})") ==
        R"({"id":9,"ok":true,"result":{)" + dxl1 + "}}");
}

TEST_CASE("shutdown asks the target to stop, and help lists the commands", "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":10,"cmd":"shutdown"})") == R"({"id":10,"ok":true,"result":{}})");
  CHECK(rig.target.shutdown_requested);
  CHECK(rig.api.handle(R"({"id":11,"cmd":"help"})") ==
        R"({"id":11,"ok":true,"result":["list","get","table","set","condition.set",)"
        R"("servo.detach","servo.attach","servo.power_cycle","servo.reboot",)"
        R"("servo.factory_reset","fault.add","fault.list",)"
        R"("fault.remove","fault.clear","scenario.load","scenario.list","trace.subscribe",)"
        R"("trace.unsubscribe","sample.subscribe","sample.unsubscribe","hand",)"
        R"("hand.play","hand.sweep","hand.move","hand.stop","physics",)"
        R"("physics.apply","physics.scene","clock.now","clock.step","stats","shutdown","help"]})");
}

TEST_CASE("The port may be left out when there is only one", "[control]") {
  FakeTarget target;
  auto& port = target.add_port("arm");
  target.add(port, "xm430-w350", 4);
  control::Api api(target);
  CHECK(api.handle(R"({"id":1,"cmd":"get","servo":4,"item":"id"})") ==
        R"({"id":1,"ok":true,"result":{"item":"id","value":4}})");
  CHECK(api.handle(R"({"id":2,"cmd":"condition.set","blocked":true})") ==
        R"({"id":2,"ok":true,"result":[{"id":4,"ambient_temperature":25.0,"supply_voltage":12.7,)"
        R"("external_load":0.0,"blocked":true}]})");
}

// --- the id --------------------------------------------------------------------------------------

TEST_CASE("The id is echoed as given, and is null when the request has none", "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":42,"cmd":"clock.now"})").starts_with(R"({"id":42,"ok":true,)"));
  CHECK(
      rig.api.handle(R"({"id":"abc","cmd":"clock.now"})").starts_with(R"({"id":"abc","ok":true,)"));
  CHECK(rig.api.handle(R"({"id":{"run":[1,2.5]},"cmd":"clock.now"})")
            .starts_with(R"({"id":{"run":[1,2.5]},"ok":true,)"));
  CHECK(rig.api.handle(R"({"cmd":"clock.now"})").starts_with(R"({"id":null,"ok":true,)"));
  // Also on errors, as soon as the request is an object.
  CHECK(rig.api.handle(R"({"id":"x","cmd":"gett"})").starts_with(R"({"id":"x","ok":false,)"));
}

// --- malformed requests --------------------------------------------------------------------------

TEST_CASE("A line that is not JSON or not an object is refused with a null id", "[control]") {
  Rig rig;
  const std::string bad = rig.api.handle(R"({"id":1,"cmd")");
  CHECK_THAT(bad,
             Catch::StartsWith(R"({"id":null,"ok":false,"error":"not valid JSON: parse error)"));
  CHECK_THAT(rig.error(""), Catch::StartsWith("not valid JSON: "));
  CHECK_THAT(rig.error(R"({"cmd":"list"} {"cmd":"list"})"), Catch::StartsWith("not valid JSON: "));
  CHECK(rig.api.handle(R"([1,2])") ==
        R"({"id":null,"ok":false,"error":"a request must be a JSON object, e.g. )"
        R"({\"id\":1,\"cmd\":\"list\"}"})");
  CHECK(rig.error("7") == R"(a request must be a JSON object, e.g. {"id":1,"cmd":"list"})");
  // Bytes that are not UTF-8 still make a reply that is JSON.
  CHECK(json::parse(rig.api.handle("\"\xFF\xFE"))["ok"] == false);
  // A runaway string is quoted only in part.
  CHECK(rig.error("\"" + std::string(100000, 'a')).size() < 300);
}

TEST_CASE("A deeply nested request is refused without exhausting the stack", "[control]") {
  Rig rig;
  const std::string deep =
      R"({"id":)" + std::string(100000, '[') + "1" + std::string(100000, ']') + R"(,"cmd":"list"})";
  CHECK(rig.error(deep) == "the request nests deeper than 32 levels");
}

TEST_CASE("A request without a known cmd is refused naming the commands", "[control]") {
  Rig rig;
  const std::string commands =
      "(commands: list, get, table, set, condition.set, servo.detach, servo.attach, "
      "servo.power_cycle, servo.reboot, servo.factory_reset, fault.add, fault.list, "
      "fault.remove, fault.clear, scenario.load, scenario.list, trace.subscribe, "
      "trace.unsubscribe, sample.subscribe, sample.unsubscribe, hand, hand.play, hand.sweep, "
      "hand.move, hand.stop, physics, physics.apply, physics.scene, clock.now, clock.step, stats, "
      "shutdown, help)";
  CHECK(rig.error(R"({"id":1})") == "\"cmd\" is required " + commands);
  CHECK(rig.error(R"({"id":1,"cmd":3})") == R"("cmd" must be a string)");
  CHECK(rig.error(R"({"id":1,"cmd":"gett"})") == "unknown command \"gett\" " + commands);
}

TEST_CASE("A field the command does not take is refused, to catch typos", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"itme":"id"})") ==
        R"(unknown field "itme" for get (it takes port, servo, item, address, size))");
  CHECK(rig.error(R"({"cmd":"list","foo":1})") ==
        R"(unknown field "foo" for list (it takes no arguments))");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","supply":11})") ==
        R"(unknown field "supply" for condition.set (it takes port, servo, ambient_temperature, )"
        R"(supply_voltage, external_load, blocked))");
}

TEST_CASE("Arguments of the wrong type are refused naming the argument", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":"1","item":"id"})") ==
        R"("servo" must be an integer)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1.5,"item":"id"})") ==
        R"("servo" must be an integer)");
  CHECK(rig.error(R"({"cmd":"get","port":0,"servo":1,"item":"id"})") ==
        R"("port" must be a string)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"item":146})") ==
        R"("item" must be a string)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"led","value":true})") ==
        R"("value" must be an integer)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"led","value":1.0})") ==
        R"("value" must be an integer)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"led",)"
                  R"("value":18446744073709551615})") == R"("value" is too large)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","blocked":1})") ==
        R"("blocked" must be true or false)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","supply_voltage":"12"})") ==
        R"("supply_voltage" must be a number)");
  CHECK(rig.error(R"({"cmd":"clock.step","ms":"10"})") == R"("ms" must be a number)");
}

TEST_CASE("Missing or contradictory arguments are refused saying what is needed", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","item":"id"})") == R"("servo" is required)");
  CHECK(rig.error(R"({"cmd":"get","servo":1,"item":"id"})") ==
        R"("port" is required: there are 2 ports (dxl0, dxl1))");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1})") ==
        R"(get needs "item", or "address" and "size")");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"address":132})") ==
        R"("size" is required)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"item":"id","address":7})") ==
        R"(give "item" or "address" and "size", not both)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"led"})") ==
        R"("value" is required)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","servo":1})") ==
        "condition.set needs at least one of ambient_temperature, supply_voltage, external_load, "
        "blocked");
}

TEST_CASE("Unknown ports, servos and items are refused naming what exists", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"get","port":"dxl9","servo":1,"item":"id"})") ==
        R"(port "dxl9" does not exist (ports: dxl0, dxl1))");
  CHECK(rig.error(R"({"cmd":"stats","port":"dxl9"})") ==
        R"(port "dxl9" does not exist (ports: dxl0, dxl1))");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":9,"item":"id"})") ==
        "no servo 9 on dxl0 (servos: 1, 2)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl1","servo":1,"blocked":true})") ==
        "no servo 1 on dxl1 (servos: 3)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_temp"})") ==
        R"(xm430-w350 has no item "present_temp")");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl1","servo":3,"item":"present_input_voltage",)"
                  R"("value":1})") == R"(ax-12a has no item "present_input_voltage")");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl1","servo":3,"address":49,"size":2})") ==
        "address 49 size 2 is outside the control table of ax-12a (0 ~ 49)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl1","servo":3,"address":-1,"size":1})") ==
        "address -1 size 1 is outside the control table of ax-12a (0 ~ 49)");
  CHECK(rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"address":0,"size":5})") ==
        R"("size" must be 1 ~ 4)");
}

TEST_CASE("A value that does not fit the item is refused and changes nothing", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"present_temperature",)"
                  R"("value":300})") == "value 300 does not fit present_temperature (1 byte)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"present_temperature",)"
                  R"("value":-1})") == "value -1 does not fit present_temperature (1 byte)");
  CHECK(rig.error(R"({"cmd":"set","port":"dxl0","servo":1,"item":"present_current",)"
                  R"("value":40000})") == "value 40000 does not fit present_current (2 bytes)");
  CHECK(rig.xm1.table().get("present_temperature") == 25);
  CHECK(rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"present_current",)"
                   R"("value":-32768})")["value"] == -32768);
}

TEST_CASE("condition.set refuses values outside sane ranges and changes nothing", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","servo":1,"supply_voltage":150})") ==
        R"("supply_voltage" must be 0 ~ 100 V, got 150)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","servo":1,"ambient_temperature":-60,)"
                  R"("blocked":true})") ==
        R"("ambient_temperature" must be -50 ~ 200 °C, got -60)");
  CHECK(rig.error(R"({"cmd":"condition.set","port":"dxl0","servo":1,"external_load":1e6})") ==
        R"("external_load" must be -1000 ~ 1000 N·m, got 1000000.0)");
  CHECK(!rig.xm1.motion().conditions().blocked);
}

TEST_CASE("clock.step needs the manual clock and one positive, bounded step", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"clock.step"})") == R"(clock.step needs one of "ms", "us" or "ns")");
  CHECK(rig.error(R"({"cmd":"clock.step","ms":1,"ns":5})") ==
        R"(clock.step takes only one of "ms", "us" or "ns")");
  CHECK(rig.error(R"({"cmd":"clock.step","ms":0})") == R"("ms" must be positive)");
  CHECK(rig.error(R"({"cmd":"clock.step","ns":-5})") == R"("ns" must be positive)");
  CHECK(rig.error(R"({"cmd":"clock.step","us":0.0001})") == R"("us" must be at least 1 ns)");
  CHECK(rig.error(R"({"cmd":"clock.step","ms":3600001})") ==
        "one clock.step moves at most 3600000 ms");
  CHECK(rig.target.now() == sim::SimTime{});
  rig.target.manual = false;
  CHECK(rig.error(R"({"cmd":"clock.step","ms":10})") == "clock.step needs --timing manual");
  CHECK(rig.target.now() == sim::SimTime{});
}

TEST_CASE("Servos sharing an ID cannot be addressed one by one", "[control]") {
  Rig rig;
  rig.target.add(rig.dxl1, "ax-12a", 3);
  CHECK(rig.error(R"({"cmd":"get","port":"dxl1","servo":3,"item":"id"})") ==
        "2 servos on dxl1 have ID 3: the control API cannot tell them apart");
  // The whole port still can be.
  CHECK(rig.result(R"({"cmd":"condition.set","port":"dxl1","blocked":true})").size() == 2);
}

TEST_CASE("A detached servo is silent until attached, and then boots from its RAM defaults",
          "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"torque_enable","value":1})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"led","value":1})");
  CHECK(rig.result(R"({"cmd":"servo.detach","port":"dxl0","servo":1})") ==
        json::parse(R"({"attached":false,"booting":false})"));
  CHECK(rig.xm1.table().get("torque_enable") == 0);  // no power, no torque
  rig.dxl0.bus.receive(wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}}),
                       rig.target.scheduler.now(), 57600);
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  CHECK(rig.dxl0.link.deliveries().empty());
  CHECK(rig.error(R"({"cmd":"servo.detach","port":"dxl0","servo":1})") ==
        "servo 1 on dxl0 is already detached");
  CHECK(rig.result(R"({"cmd":"list"})")["ports"][0]["servos"][0]["attached"] == false);
  CHECK(rig.result(R"({"cmd":"servo.attach","port":"dxl0","servo":1})") ==
        json::parse(R"({"attached":true,"booting":true})"));
  CHECK(rig.xm1.table().get("led") == 0);  // RAM back to its initial values
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  rig.dxl0.bus.receive(wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}}),
                       rig.target.scheduler.now(), 57600);
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  CHECK(rig.dxl0.link.deliveries().size() == 1);
  CHECK(rig.error(R"({"cmd":"servo.attach","port":"dxl0","servo":1})") ==
        "servo 1 on dxl0 is attached (servo.power_cycle restarts it)");
}

TEST_CASE("A power cycle reboots an attached servo and keeps its EEPROM", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"return_delay_time","value":0})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"led","value":1})");
  CHECK(rig.result(R"({"cmd":"servo.power_cycle","port":"dxl0","servo":2})") ==
        json::parse(R"({"attached":true,"booting":true})"));
  CHECK(rig.xm2.table().get("led") == 0);
  CHECK(rig.xm2.table().get("return_delay_time") == 0);
  rig.target.scheduler.advance_by(std::chrono::milliseconds(500));
  CHECK(rig.result(R"({"cmd":"servo.power_cycle","port":"dxl0","servo":2})")["booting"] == true);
}

TEST_CASE("servo.reboot and servo.factory_reset act as the instructions a tool sends",
          "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"led","value":1})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"return_delay_time","value":0})");
  CHECK(rig.result(R"({"cmd":"servo.reboot","port":"dxl0","servo":2})") ==
        json::parse(R"({"servo":2,"attached":true,"booting":true})"));
  CHECK(rig.xm2.table().get("led") == 0);                // RAM back to its initial values
  CHECK(rig.xm2.table().get("return_delay_time") == 0);  // EEPROM kept
  CHECK(rig.error(R"({"cmd":"servo.reboot","port":"dxl0","servo":2})") ==
        "servo 2 on dxl0 is booting: it hears no Reboot until it is up");
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  CHECK(rig.dxl0.link.deliveries().empty());  // nothing on the line
  // Keeping the ID: everything else, EEPROM included, back to the factory's values.
  rig.result(R"({"cmd":"set","port":"dxl0","servo":2,"item":"id","value":7})");
  CHECK(rig.result(R"({"cmd":"servo.factory_reset","port":"dxl0","servo":7,"keep":"id"})") ==
        json::parse(R"({"servo":7,"attached":true,"booting":true})"));
  CHECK(rig.xm2.table().get("return_delay_time") == 250);
  rig.target.scheduler.advance_by(std::chrono::seconds(1));
  // Everything: the ID goes back to 1, as the servo's status would have said.
  CHECK(rig.result(R"({"cmd":"servo.factory_reset","port":"dxl0","servo":7})")["servo"] == 1);
  CHECK(rig.xm2.id() == 1);
  CHECK(rig.error(R"({"cmd":"servo.factory_reset","port":"dxl0","servo":1})") ==
        "2 servos on dxl0 have ID 1: the control API cannot tell them apart");
  CHECK(rig.error(R"({"cmd":"servo.factory_reset","port":"dxl1","servo":3,"keep":"all"})") ==
        R"("keep" must be "none", "id" or "id_baud", not "all")");
  CHECK(rig.error(R"({"cmd":"servo.factory_reset","port":"dxl1","servo":3,"keep":"id"})") ==
        "servo 3 on dxl1 does not speak Protocol 2.0, whose Factory Reset alone can keep the ID "
        "or baud");
  rig.result(R"({"cmd":"servo.detach","port":"dxl1","servo":3})");
  CHECK(rig.error(R"({"cmd":"servo.reboot","port":"dxl1","servo":3})") ==
        "servo 3 on dxl1 is detached: it hears no Reboot");
}

// --- faults ------------------------------------------------------------------------------------

TEST_CASE("fault.add returns a rule id, fault.list shows the rule and its counters", "[control]") {
  Rig rig;
  CHECK(
      rig.result(
          R"({"cmd":"fault.add","rule":{"action":"drop_reply","match":{"port":"dxl0","servos":[2],"instruction":"ping"},"count":1}})") ==
      json::parse(R"({"rule":1})"));
  CHECK(rig.result(R"({"cmd":"fault.add","rule":{"action":"slow","us":100}})") ==
        json::parse(R"({"rule":2})"));
  // A ping of servo 2 is dropped once.
  rig.dxl0.bus.receive(wire::encode_instruction({wire::Protocol::V2, 2, wire::Ping{}}),
                       rig.target.now(), 57600);
  rig.target.step_clock(10ms);
  CHECK(rig.dxl0.link.deliveries().empty());
  CHECK(rig.result(R"({"cmd":"fault.list"})") == json::parse(R"([
    {"id":1,"rule":{"action":"drop_reply","match":{"port":"dxl0","servos":[2],"instruction":["ping"]},
                    "probability":1.0,"count":1,"after":0,"from_ms":0.0},
     "matched":1,"fired":1,"active":false},
    {"id":2,"rule":{"action":"slow","match":{},"probability":1.0,"after":0,"from_ms":0.0,"us":100},
     "matched":1,"fired":1,"active":true}])"));
  CHECK(rig.result(R"({"cmd":"stats","port":"dxl0"})")["dxl0"]["faults_injected"] == 2);
}

TEST_CASE("An injected hardware error shows on the bus and is gone after fault.remove and Reboot",
          "[control]") {
  Rig rig;
  const json added = rig.result(
      R"({"cmd":"fault.add","rule":{"action":"hardware_error","kind":"overload","match":{"port":"dxl0","servos":[1]}}})");
  rig.target.step_clock(2ms);
  CHECK(rig.result(
            R"({"cmd":"get","port":"dxl0","servo":1,"item":"hardware_error_status"})")["value"] ==
        32);
  CHECK(rig.result(R"({"cmd":"fault.remove","rule":)" + added["rule"].dump() + "}") == added);
  rig.dxl0.bus.power_on(rig.xm1);  // a reboot: the error does not come back
  rig.target.step_clock(1s);
  CHECK(rig.result(
            R"({"cmd":"get","port":"dxl0","servo":1,"item":"hardware_error_status"})")["value"] ==
        0);
}

TEST_CASE("fault.clear removes every rule and says how many", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"fault.add","rule":{"action":"drop_reply"}})");
  rig.result(R"({"cmd":"fault.add","rule":{"action":"noise"}})");
  CHECK(rig.result(R"({"cmd":"fault.clear"})") == json::parse(R"({"removed":2})"));
  CHECK(rig.result(R"({"cmd":"fault.list"})") == json::array());
}

TEST_CASE("A bad fault rule is refused naming the member, and nothing is added", "[control]") {
  Rig rig;
  CHECK(rig.error(R"({"cmd":"fault.add"})").rfind("\"rule\" is required", 0) == 0);
  CHECK(
      rig.error(R"({"cmd":"fault.add","rule":{"action":"drop_reply","match":{"servos":[300]}}})") ==
      "rule/match/servos/0: must be an integer from 0 to 252, not 300");
  CHECK(
      rig.error(R"({"cmd":"fault.add","rule":{"action":"drop_reply","match":{"port":"dxl9"}}})") ==
      "rule/match/port: port \"dxl9\" does not exist (ports: dxl0, dxl1)");
  CHECK(rig.error(R"({"cmd":"fault.add","rule":"drop"})") ==
        "rule: a rule must be a JSON object with at least \"action\"");
  CHECK(rig.error(R"({"cmd":"fault.remove","rule":7})") == "no fault rule 7 (there are none)");
  rig.result(R"({"cmd":"fault.add","rule":{"action":"drop_reply"}})");
  CHECK(rig.error(R"({"cmd":"fault.remove","rule":7})") == "no fault rule 7 (rules: 1)");
  CHECK(rig.error(R"({"cmd":"fault.remove","rule":"1"})") == "\"rule\" must be an integer");
  CHECK(rig.result(R"({"cmd":"fault.list"})").size() == 1);
}

// --- trace events and scenarios ------------------------------------------------------------------

TEST_CASE("trace.subscribe registers the connection for one port or all, trace.unsubscribe ends it",
          "[control]") {
  Rig rig;
  const control::Connection five{5, [](const std::string& /*line*/) {}};
  const control::Connection six{6, [](const std::string& /*line*/) {}};
  CHECK(rig.api.handle(R"({"id":1,"cmd":"trace.subscribe","port":"dxl1"})", &five) ==
        R"({"id":1,"ok":true,"result":{"ports":["dxl1"]}})");
  CHECK(rig.target.subscriptions.at(5) == std::vector<std::string>{"dxl1"});
  CHECK(rig.api.handle(R"({"id":2,"cmd":"trace.subscribe"})", &six) ==
        R"({"id":2,"ok":true,"result":{"ports":["dxl0","dxl1"]}})");
  CHECK(rig.target.subscriptions.at(6).empty());
  CHECK(rig.api.handle(R"({"id":3,"cmd":"trace.unsubscribe"})", &five) ==
        R"({"id":3,"ok":true,"result":{}})");
  CHECK(rig.target.subscriptions.count(5) == 0);
  // Without a connection there is nowhere to send events.
  CHECK(rig.error(R"({"cmd":"trace.subscribe"})") ==
        "trace.subscribe needs a connection to send events to");
}

TEST_CASE("scenario.load runs each step at its time on the simulated clock", "[control]") {
  Rig rig;
  CHECK(rig.result(R"({"cmd":"scenario.load","scenario":{"description":"servo 2 overheats","steps":[
      {"at_ms":0,"cmd":"condition.set","port":"dxl0","servo":2,"ambient_temperature":40},
      {"at_ms":100,"cmd":"fault.add","rule":{"action":"hardware_error","kind":"overheating","match":{"port":"dxl0","servos":[2]},"until_ms":50}},
      {"at_ms":200,"cmd":"servo.detach","port":"dxl0","servo":1}]}})") ==
        json::parse(R"({"steps":3,"scenario":1})"));
  CHECK(rig.result(R"({"cmd":"fault.list"})").empty());
  rig.target.step_clock(1ms);
  CHECK(rig.xm2.motion().conditions().ambient_c == 40);
  rig.target.step_clock(100ms);
  CHECK(rig.xm2.motion().injected() == model::fault_set(model::HardwareFault::Overheating));
  rig.target.step_clock(60ms);  // the rule's window closed
  CHECK(rig.xm2.motion().injected() == 0);
  CHECK(rig.dxl0.bus.attached(rig.xm1));
  rig.target.step_clock(50ms);
  CHECK_FALSE(rig.dxl0.bus.attached(rig.xm1));
  CHECK(rig.target.warnings.empty());
}

TEST_CASE("scenario.load reads a file, and a step that fails when it runs is reported",
          "[control]") {
  Rig rig;
  const std::string path = "scenario_load_test.json";
  std::ofstream(path) << R"({"steps":[{"at_ms":5,"cmd":"servo.attach","port":"dxl0","servo":1}]})";
  CHECK(rig.result(R"({"cmd":"scenario.load","file":")" + path + R"("})") ==
        json::parse(R"({"steps":1,"scenario":1})"));
  rig.target.step_clock(10ms);  // servo 1 is attached already: the step fails
  REQUIRE(rig.target.warnings.size() == 1);
  CHECK(rig.target.warnings.front() ==
        "scenario scenario_load_test.json /steps/0: servo 1 on dxl0 is attached "
        "(servo.power_cycle restarts it)");
  std::remove(path.c_str());
  CHECK(rig.error(R"({"cmd":"scenario.load","file":"no/such/file.json"})") ==
        "no/such/file.json: cannot be read");
  // A number too large for a double is nlohmann's out_of_range, not a parse_error.
  std::ofstream(path) << R"({"steps":[{"at_ms":1e999,"cmd":"list"}]})";
  CHECK_THAT(rig.error(R"({"cmd":"scenario.load","file":")" + path + R"("})"),
             Catch::StartsWith(path + ": not valid JSON: "));
  std::remove(path.c_str());
}

TEST_CASE("scenario.load refuses a FIFO, a device and a directory without reading them",
          "[control]") {
  // Found by scripts/reliability: opening a FIFO blocked the daemon (bus and control API) until
  // a writer came, and /dev/zero would have been read until memory ran out.
  Rig rig;
  const std::string fifo = "scenario_load_test.fifo";
  std::remove(fifo.c_str());
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(rig.error(R"({"cmd":"scenario.load","file":")" + fifo + R"("})") ==
        fifo + ": is not a regular file");
  std::remove(fifo.c_str());
  CHECK(rig.error(R"({"cmd":"scenario.load","file":"/dev/zero"})") ==
        "/dev/zero: is not a regular file");
  CHECK(rig.error(R"({"cmd":"scenario.load","file":"/"})") == "/: is not a regular file");
}

TEST_CASE("A bad scenario is refused naming the step and the reason, and nothing runs",
          "[control]") {
  Rig rig;
  const auto load = [&](const std::string& scenario) {
    return rig.error(R"({"cmd":"scenario.load","scenario":)" + scenario + "}");
  };
  CHECK(load("[]") == "scenario: a scenario must be a JSON object with \"steps\"");
  CHECK(load(R"({"steps":{}})") == "scenario/steps: must be an array of steps");
  CHECK(load(R"({"steps":[],"speed":2})") ==
        "scenario/speed: unknown member (a scenario has steps and description)");
  CHECK(load(R"({"steps":[{"cmd":"fault.clear"}]})") ==
        "scenario/steps/0/at_ms: must be the step's time in ms after loading, from 0 to 86400000");
  CHECK(load(R"({"steps":[{"at_ms":1,"cmd":"stats"}]})")
            .rfind("scenario/steps/0/cmd: \"stats\" cannot be a step", 0) == 0);
  CHECK(
      load(
          R"({"steps":[{"at_ms":0,"cmd":"fault.clear"},{"at_ms":1,"cmd":"servo.detach","port":"dxl0","servo":9}]})") ==
      "scenario/steps/1: no servo 9 on dxl0 (servos: 1, 2)");
  CHECK(load(R"({"steps":[{"at_ms":0,"cmd":"fault.add","rule":{"action":"noise","bytes":0}}]})") ==
        "scenario/steps/0: rule/bytes: must be an integer from 1 to 1024, not 0");
  CHECK(load(R"({"steps":[{"at_ms":0,"cmd":"set","port":"dxl0","servo":1,"colour":1}]})")
            .rfind("scenario/steps/0: unknown field \"colour\" for set", 0) == 0);
  CHECK(rig.error(R"({"cmd":"scenario.load"})") ==
        "give either \"file\" (a scenario file's path) or \"scenario\" (the scenario itself)");
  // The first step was valid, but the scenario was refused whole.
  rig.target.step_clock(10ms);
  CHECK(rig.target.warnings.empty());
  CHECK(rig.dxl0.bus.attached(rig.xm1));
  CHECK(rig.result(R"({"cmd":"scenario.list"})") == json::array());  // none was recorded
}

TEST_CASE(
    "physics, physics.apply and physics.scene are refused when the daemon simulates no physics",
    "[control][physics]") {
  Rig rig;
  const std::string why =
      "this daemon simulates no physics: its config has no \"physics\" (docs/physics.md)";
  CHECK(rig.error(R"({"cmd":"physics"})") == why);
  CHECK(rig.error(R"({"cmd":"physics.apply","joint":"shoulder","torque_nm":1})") == why);
  CHECK(rig.error(R"({"cmd":"physics.scene"})") == why);
  // A scenario step is checked the same way before it is scheduled.
  CHECK(control::Api::check(rig.target, json::parse(R"({"cmd":"physics"})")) == why);
  CHECK(rig.error(R"({"cmd":"physics","body":"link"})") ==
        "unknown field \"body\" for physics (it takes joint)");
}
