// Read-only connections (docs/control-api.md "Read-only connections"): every command that changes
// anything is refused, and refused before it changes anything; the looking commands run.
#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <string>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "control/connection.hpp"
#include "ports_target.hpp"

using nlohmann::json;

namespace dxlemu::test::read_only {

constexpr std::string_view kRefusal =
    "read-only: this connection may only look (dxlemu run --web-read-only)";

/// dxl0: two XM430-W350 (IDs 1 and 2); a rule of faults in place.
struct Rig : ApiRequests<Rig> {
  PortsTarget target;
  PortsTarget::Port& dxl0 = target.add_port("dxl0");
  model::Servo& xm1 = target.add(dxl0, "xm430-w350", 1);
  model::Servo& xm2 = target.add(dxl0, "xm430-w350", 2);
  control::Api api{target};
  control::Connection looker{7, [](const std::string& /*line*/) {}, true};

  /// The reply to `request` sent on the read-only connection.
  json on_read_only(const json& request) {
    return json::parse(api.handle(request.dump(), &looker));
  }

  /// Everything a command could change that the API shows, and what the target recorded.
  json everything() {
    json out;
    for (const char* request :
         {R"({"cmd":"list"})", R"({"cmd":"fault.list"})", R"({"cmd":"scenario.list"})",
          R"({"cmd":"clock.now"})", R"({"cmd":"stats"})", R"({"cmd":"hand"})",
          R"({"cmd":"table","servo":1})", R"({"cmd":"table","servo":2})"}) {
      out[request] = result(request);
    }
    for (const auto* servo : {&xm1, &xm2}) {
      out["conditions"].push_back(servo->motion().conditions().ambient_c);
    }
    out["shutdown"] = target.shutdown_requested;
    out["warnings"] = target.warnings;
    out["pending"] = target.scheduler.pending();  // nothing scheduled (a scenario, a hand)
    return out;
  }
};

/// A request for each command that only looks.
const std::map<std::string, json>& looking() {
  static const std::map<std::string, json> requests = {
      {"help", {{"cmd", "help"}}},
      {"list", {{"cmd", "list"}}},
      {"get", {{"cmd", "get"}, {"servo", 1}, {"item", "present_position"}}},
      {"table", {{"cmd", "table"}, {"servo", 1}}},
      {"stats", {{"cmd", "stats"}}},
      {"fault.list", {{"cmd", "fault.list"}}},
      {"scenario.list", {{"cmd", "scenario.list"}}},
      {"hand", {{"cmd", "hand"}}},
      {"physics", {{"cmd", "physics"}}},  // refused, but for want of a world
      {"clock.now", {{"cmd", "clock.now"}}},
      {"trace.subscribe", {{"cmd", "trace.subscribe"}}},
      {"trace.unsubscribe", {{"cmd", "trace.unsubscribe"}}},
      {"sample.subscribe",
       json::parse(
           R"({"cmd":"sample.subscribe","items":[{"servo":1,"item":"led"}],"period_ms":10})")},
      {"sample.unsubscribe", {{"cmd", "sample.unsubscribe"}}},
      {"physics.scene", {{"cmd", "physics.scene"}}},  // refused, but for want of a world
  };
  return requests;
}

/// A request for each command that changes something: each would succeed on another connection
/// unless noted.
const std::map<std::string, json>& changing() {
  static const std::map<std::string, json> requests = {
      {"set", {{"cmd", "set"}, {"servo", 1}, {"item", "goal_position"}, {"value", 100}}},
      {"condition.set", {{"cmd", "condition.set"}, {"servo", 1}, {"ambient_temperature", 50}}},
      {"servo.detach", {{"cmd", "servo.detach"}, {"servo", 1}}},
      {"servo.attach", {{"cmd", "servo.attach"}, {"servo", 1}}},  // attached: would be refused
      {"servo.power_cycle", {{"cmd", "servo.power_cycle"}, {"servo", 2}}},
      {"servo.reboot", {{"cmd", "servo.reboot"}, {"servo", 2}}},
      {"servo.factory_reset", {{"cmd", "servo.factory_reset"}, {"servo", 2}}},
      {"fault.add", json::parse(R"({"cmd":"fault.add","rule":{"action":"silence"}})")},
      {"fault.remove", {{"cmd", "fault.remove"}, {"rule", 1}}},
      {"fault.clear", {{"cmd", "fault.clear"}}},
      {"scenario.load", json::parse(R"({"cmd":"scenario.load","scenario":{"steps":[)"
                                    R"({"at_ms":0,"cmd":"servo.detach","servo":2}]}})")},
      {"hand.play", {{"cmd", "hand.play"}, {"file", "wave"}}},
      {"hand.sweep", {{"cmd", "hand.sweep"}}},
      {"hand.move", {{"cmd", "hand.move"}, {"joint", 1}, {"position", 30}}},
      {"hand.stop", {{"cmd", "hand.stop"}}},
      {"physics.apply", {{"cmd", "physics.apply"}, {"joint", "shoulder"}, {"torque_nm", 1}}},
      {"clock.step", {{"cmd", "clock.step"}, {"ms", 10}}},
      {"shutdown", {{"cmd", "shutdown"}}},
  };
  return requests;
}

TEST_CASE("Every command is either a looking or a changing one", "[control][read_only]") {
  // A new command must be added to one of the lists above (and its flag in the command table
  // set to match): this fails until it is.
  std::set<std::string> listed;
  for (const auto& [name, request] : looking()) {
    listed.insert(name);
  }
  for (const auto& [name, request] : changing()) {
    listed.insert(name);
  }
  const auto names = control::Api::command_names();
  CHECK(std::set<std::string>(names.begin(), names.end()) == listed);
  CHECK(names.size() == looking().size() + changing().size());
}

TEST_CASE("A read-only connection may run every looking command", "[control][read_only]") {
  Rig rig;
  for (const auto& [name, request] : looking()) {
    CAPTURE(name);
    const json reply = rig.on_read_only(request);
    if (name == "physics" || name == "physics.scene") {
      CHECK(reply["error"] != kRefusal);
    } else {
      CHECK(reply["ok"] == true);
    }
  }
  CHECK(rig.target.subscriptions.empty());  // trace.subscribe and .unsubscribe both ran
}

TEST_CASE("A read-only connection is refused every changing command, and nothing changes",
          "[control][read_only]") {
  Rig rig;
  rig.result(R"({"cmd":"fault.add","rule":{"action":"noise","bytes":1,"probability":0}})");
  const json before = rig.everything();
  for (const auto& [name, request] : changing()) {
    CAPTURE(name);
    json with_id = request;
    with_id["id"] = 42;
    CHECK(rig.on_read_only(with_id) ==
          json({{"id", 42}, {"ok", false}, {"error", std::string(kRefusal)}}));
  }
  const json after = rig.everything();
  CHECK(after == before);
}

TEST_CASE("The refusal comes before any other check, and other connections are not read-only",
          "[control][read_only]") {
  Rig rig;
  // Even a malformed changing request is refused as read-only: nothing of it is looked at.
  CHECK(rig.on_read_only({{"cmd", "set"}, {"colour", 1}})["error"] == kRefusal);
  // An unknown command is still unknown.
  CHECK(rig.on_read_only({{"cmd", "gett"}})["error"].get<std::string>().starts_with(
      "unknown command"));
  // The same request on an ordinary connection, or none (a scenario step), runs.
  const control::Connection ordinary{8, [](const std::string& /*line*/) {}};
  CHECK(json::parse(rig.api.handle(R"({"cmd":"clock.step","ms":1})", &ordinary))["ok"] == true);
  CHECK(rig.result(R"({"cmd":"clock.step","ms":1})")["ms"] == 2.0);
}

}  // namespace dxlemu::test::read_only
