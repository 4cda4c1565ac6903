// scenario.list (docs/control-api.md): every scenario loaded, with its steps' progress on the
// simulated clock; scenario.load's result numbers the scenario.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "control/scenario.hpp"
#include "ports_target.hpp"

using nlohmann::json;
using namespace std::chrono_literals;

namespace dxlemu::test::scenario_list {

/// dxl0: two XM430-W350 (IDs 1 and 2).
struct Rig : ApiRequests<Rig> {
  PortsTarget target;
  PortsTarget::Port& dxl0 = target.add_port("dxl0");
  model::Servo& xm1 = target.add(dxl0, "xm430-w350", 1);
  model::Servo& xm2 = target.add(dxl0, "xm430-w350", 2);
  control::Api api{target};
};

TEST_CASE("scenario.list shows each scenario's steps done, failed and the next one's time",
          "[control][scenario_list]") {
  Rig rig;
  CHECK(rig.result(R"({"cmd":"scenario.list"})") == json::array());
  rig.target.step_clock(50ms);
  // Steps out of time order: they run in time order all the same.
  CHECK(rig.result(R"({"cmd":"scenario.load","scenario":{"steps":[
      {"at_ms":200,"cmd":"servo.detach","port":"dxl0","servo":1},
      {"at_ms":0,"cmd":"condition.set","port":"dxl0","servo":2,"ambient_temperature":40},
      {"at_ms":100,"cmd":"servo.attach","port":"dxl0","servo":2}]}})") ==
        json::parse(R"({"steps":3,"scenario":1})"));
  CHECK(rig.result(R"({"cmd":"scenario.list"})") ==
        json::parse(R"([{"scenario":1,"origin":"request","steps":3,"done":0,"failed":0,)"
                    R"("next_at_ms":50.0,"loaded_at_ms":50.0}])"));
  rig.target.step_clock(1ms);
  CHECK(rig.result(R"({"cmd":"scenario.list"})")[0]["done"] == 1);
  CHECK(rig.result(R"({"cmd":"scenario.list"})")[0]["next_at_ms"] == 150.0);
  rig.target.step_clock(100ms);  // servo 2 is attached already: the step fails
  json listed = rig.result(R"({"cmd":"scenario.list"})");
  CHECK(listed[0]["done"] == 2);
  CHECK(listed[0]["failed"] == 1);
  CHECK(listed[0]["next_at_ms"] == 250.0);
  CHECK(rig.target.warnings.size() == 1);
  rig.target.step_clock(100ms);
  listed = rig.result(R"({"cmd":"scenario.list"})");
  CHECK(listed[0]["done"] == 3);
  CHECK(listed[0]["failed"] == 1);
  CHECK(listed[0]["next_at_ms"] == nullptr);  // all run
  CHECK_FALSE(rig.dxl0.bus.attached(rig.xm1));
}

TEST_CASE("Scenarios are numbered in load order and a file's origin is its path",
          "[control][scenario_list]") {
  Rig rig;
  const std::string path = "scenario_list_test.json";
  std::ofstream(path) << R"({"steps":[{"at_ms":5,"cmd":"fault.clear"}]})";
  CHECK(rig.result(R"({"cmd":"scenario.load","file":")" + path + R"("})") ==
        json::parse(R"({"steps":1,"scenario":1})"));
  std::remove(path.c_str());
  // A refused scenario takes no number.
  rig.error(R"({"cmd":"scenario.load","scenario":{"steps":[{"at_ms":0,"cmd":"stats"}]}})");
  rig.target.step_clock(2ms);
  CHECK(rig.result(R"({"cmd":"scenario.load","scenario":{"steps":[]}})") ==
        json::parse(R"({"steps":0,"scenario":2})"));
  rig.target.step_clock(3ms);
  CHECK(rig.result(R"({"cmd":"scenario.list"})") ==
        json::parse(R"([{"scenario":1,"origin":"scenario_list_test.json","steps":1,"done":1,)"
                    R"("failed":0,"next_at_ms":null,"loaded_at_ms":0.0},)"
                    R"({"scenario":2,"origin":"request","steps":0,"done":0,"failed":0,)"
                    R"("next_at_ms":null,"loaded_at_ms":2.0}])"));
}

TEST_CASE("A scenario scheduled at start (--scenario) is listed under the origin it is given",
          "[control][scenario_list]") {
  Rig rig;
  const control::ScheduledScenario scheduled = control::schedule_scenario(
      rig.target, json::parse(R"({"steps":[{"at_ms":10,"cmd":"fault.clear"}]})"),
      "/etc/dxlemu/start.json");
  CHECK(scheduled.number == 1);
  CHECK(scheduled.steps == 1);
  const json listed = rig.result(R"({"cmd":"scenario.list"})");
  CHECK(listed[0]["origin"] == "/etc/dxlemu/start.json");
  CHECK(listed[0]["next_at_ms"] == 10.0);
}

}  // namespace dxlemu::test::scenario_list
