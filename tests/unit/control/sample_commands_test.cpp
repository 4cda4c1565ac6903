// sample.subscribe and sample.unsubscribe (docs/control-api.md "Sampling"): control-table items
// sent to a connection every period of simulated time, on real servos and a hand-stepped clock.
#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <vector>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "control/connection.hpp"
#include "ports_target.hpp"

using namespace dxlemu;
using nlohmann::json;

namespace dxlemu::test::sample_commands {

/// dxl0: two XM430-W350 (IDs 1 and 2); dxl1: one AX-12A (ID 3). Connection 5 records its events.
struct Rig : test::ApiRequests<Rig> {
  test::PortsTarget target;
  test::PortsTarget::Port& dxl0 = target.add_port("dxl0");
  test::PortsTarget::Port& dxl1 = target.add_port("dxl1");
  model::Servo& xm1 = target.add(dxl0, "xm430-w350", 1);
  model::Servo& xm2 = target.add(dxl0, "xm430-w350", 2);
  model::Servo& ax3 = target.add(dxl1, "ax-12a", 3);
  control::Api api{target};
  std::vector<json> events;
  control::Connection five{
      5, [this](const std::string& line) { events.push_back(json::parse(line)); }};

  /// The result of `line` sent on connection 5, which must succeed.
  json on_five(const std::string& line) {
    const json r = json::parse(api.handle(line, &five));
    INFO(line << " -> " << r.dump());
    REQUIRE(r["ok"] == true);
    return r["result"];
  }
  /// The error of `line` sent on connection 5, which must fail.
  std::string refused_on_five(const std::string& line) {
    const json r = json::parse(api.handle(line, &five));
    INFO(line << " -> " << r.dump());
    REQUIRE(r["ok"] == false);
    return r["error"].get<std::string>();
  }
  void step_ms(double ms) { result(R"({"cmd":"clock.step","ms":)" + json(ms).dump() + "}"); }
  /// The events' times, s.
  std::vector<double> times() const {
    std::vector<double> out;
    for (const json& e : events) {
      out.push_back(e["t"].get<double>());
    }
    return out;
  }
};

const std::string kPosition =
    R"({"cmd":"sample.subscribe","items":[{"port":"dxl0","servo":1,"item":"present_position"}],)";

TEST_CASE("sample.subscribe names what it samples and sends every period of simulated time",
          "[control]") {
  Rig rig;
  CHECK(rig.api.handle(R"({"id":1,"cmd":"sample.subscribe","period_ms":10,"items":[)"
                       R"({"port":"dxl0","servo":1,"item":"present_position"},)"
                       R"({"servo":3,"port":"dxl1","item":"present_temperature"}]})",
                       &rig.five) ==
        R"({"id":1,"ok":true,"result":{"items":[)"
        R"({"port":"dxl0","servo":1,"item":"present_position"},)"
        R"({"port":"dxl1","servo":3,"item":"present_temperature"}],"period_ms":10}})");
  CHECK(rig.events.empty());  // the first comes a period from now
  rig.step_ms(9.999);
  CHECK(rig.events.empty());
  rig.step_ms(0.001);
  REQUIRE(rig.events.size() == 1);
  CHECK(rig.events[0].dump() == R"({"event":"sample","t":0.01,"values":[2048,25]})");
  rig.step_ms(25);
  CHECK(rig.times() == std::vector<double>{0.01, 0.02, 0.03});
}

TEST_CASE("A fractional sampling period keeps to its times without drifting", "[control]") {
  Rig rig;
  rig.step_ms(1);
  rig.on_five(kPosition + R"("period_ms":2.5})");
  rig.step_ms(10);
  CHECK(rig.times() == std::vector<double>{0.0035, 0.006, 0.0085, 0.011});
  rig.events.clear();
  rig.step_ms(1000);
  REQUIRE(rig.events.size() == 400);
  CHECK(rig.events.back()["t"] == 1.011);
}

TEST_CASE("Sampled values follow a moving servo as get reads them", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"torque_enable","value":1})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"goal_position","value":3000})");
  rig.on_five(R"({"cmd":"sample.subscribe","period_ms":50,"items":[)"
              R"({"port":"dxl0","servo":1,"item":"present_position"},)"
              R"({"port":"dxl0","servo":1,"item":"moving"},)"
              R"({"port":"dxl0","servo":2,"item":"present_position"}]})");
  rig.step_ms(2000);
  REQUIRE(rig.events.size() == 40);
  std::int64_t last = 2048;
  for (const json& e : rig.events) {
    const auto position = e["values"][0].get<std::int64_t>();
    CHECK(position >= last);  // caught up at each sample, never a stale value
    last = position;
    CHECK(e["values"][2] == 2048);  // servo 2 stays
  }
  CHECK(rig.events.front()["values"][0].get<std::int64_t>() > 2048);
  CHECK(rig.events.front()["values"][1] == 1);
  CHECK(rig.events.back()["values"] == json::parse("[3000, 0, 2048]"));
  CHECK(rig.result(R"({"cmd":"get","port":"dxl0","servo":1,"item":"present_position"})")["value"] ==
        3000);
}

TEST_CASE("A sample reads the servo the motion model has caught up to the sample's time",
          "[control]") {
  // Each event is compared with a get made as it arrives, at the same simulated time.
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"torque_enable","value":1})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"goal_position","value":4000})");
  std::vector<std::int64_t> seen;
  std::vector<std::int64_t> read;
  const control::Connection six{
      6, [&](const std::string& line) {
        seen.push_back(json::parse(line)["values"][0]);
        read.push_back(rig.result(R"({"cmd":"get","port":"dxl0",)"
                                  R"("servo":1,"item":"present_position"})")["value"]);
      }};
  const json r = json::parse(rig.api.handle(kPosition + R"("period_ms":7})", &six));
  REQUIRE(r["ok"] == true);
  rig.step_ms(300);
  REQUIRE(seen.size() == 42);
  CHECK(seen == read);
  CHECK(seen.back() > seen.front());
}

TEST_CASE("Items of two ports and a detached servo: null while it is unplugged", "[control]") {
  Rig rig;
  rig.result(R"({"cmd":"set","port":"dxl1","servo":3,"item":"return_delay_time","value":40})");
  rig.on_five(R"({"cmd":"sample.subscribe","period_ms":100,"items":[)"
              R"({"port":"dxl1","servo":3,"item":"return_delay_time"},)"
              R"({"port":"dxl0","servo":2,"item":"present_temperature"},)"
              R"({"port":"dxl1","servo":3,"item":"id"}]})");
  rig.step_ms(100);
  rig.result(R"({"cmd":"servo.detach","port":"dxl1","servo":3})");
  rig.step_ms(100);
  rig.result(R"({"cmd":"servo.attach","port":"dxl1","servo":3})");
  rig.step_ms(100);
  REQUIRE(rig.events.size() == 3);
  CHECK(rig.events[0]["values"] == json::parse("[40, 25, 3]"));
  CHECK(rig.events[1]["values"] == json::parse("[null, 25, null]"));
  CHECK(rig.events[2]["values"] == json::parse("[40, 25, 3]"));  // plugged in again
}

TEST_CASE("A sampled servo whose ID changes is still the one sampled", "[control]") {
  Rig rig;
  rig.on_five(kPosition + R"("period_ms":10})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":1,"item":"id","value":9})");
  rig.result(R"({"cmd":"set","port":"dxl0","servo":9,"item":"present_position","value":1234})");
  rig.step_ms(10);
  REQUIRE(rig.events.size() == 1);
  CHECK(rig.events[0]["values"] == json::parse("[1234]"));
}

TEST_CASE("Subscribing again replaces the sampler, sample.unsubscribe ends it", "[control]") {
  Rig rig;
  rig.on_five(kPosition + R"("period_ms":10})");
  rig.step_ms(15);
  REQUIRE(rig.events.size() == 1);
  // The old sampler's event at 20 ms is still pending: it must send nothing.
  rig.on_five(R"({"cmd":"sample.subscribe","period_ms":20,)"
              R"("items":[{"port":"dxl1","servo":3,"item":"id"}]})");
  rig.step_ms(45);
  CHECK(rig.times() == std::vector<double>{0.01, 0.035, 0.055});
  CHECK(rig.events[1]["values"] == json::parse("[3]"));
  CHECK(rig.on_five(R"({"cmd":"sample.unsubscribe"})") == json::parse(R"({"stopped":true})"));
  rig.step_ms(100);
  CHECK(rig.events.size() == 3);
  CHECK(rig.on_five(R"({"cmd":"sample.unsubscribe"})") == json::parse(R"({"stopped":false})"));
  // Each connection has its own sampler: another's unsubscribing ends none of connection 5's.
  rig.on_five(kPosition + R"("period_ms":10})");
  const control::Connection six{6, [](const std::string& /*line*/) {}};
  CHECK(json::parse(rig.api.handle(R"({"cmd":"sample.unsubscribe"})", &six))["result"] ==
        json::parse(R"({"stopped":false})"));
  rig.step_ms(10);
  CHECK(rig.events.size() == 4);
}

TEST_CASE("Closing a connection ends its sampler and its trace subscription", "[control]") {
  Rig rig;
  rig.on_five(kPosition + R"("period_ms":10})");
  rig.on_five(R"({"cmd":"trace.subscribe"})");
  std::vector<std::string> six_events;
  const control::Connection six{6, [&](const std::string& line) { six_events.push_back(line); }};
  REQUIRE(json::parse(rig.api.handle(kPosition + R"("period_ms":10})", &six))["ok"] == true);
  rig.step_ms(5);
  rig.api.closed(5);
  CHECK(rig.target.subscriptions.count(5) == 0);
  rig.step_ms(100);
  CHECK(rig.events.empty());
  CHECK(six_events.size() == 10);  // the other connection goes on
  rig.api.closed(7);               // a connection that had nothing
  CHECK(rig.on_five(R"({"cmd":"sample.unsubscribe"})") == json::parse(R"({"stopped":false})"));
}

TEST_CASE("A sampler whose Api is gone sends nothing at its pending event", "[control]") {
  Rig rig;
  auto api = std::make_unique<control::Api>(rig.target);
  REQUIRE(json::parse(api->handle(kPosition + R"("period_ms":10})", &rig.five))["ok"] == true);
  api.reset();
  rig.target.scheduler.advance_by(std::chrono::milliseconds(50));
  CHECK(rig.events.empty());
}

TEST_CASE("sample.subscribe refuses bad items and periods clearly and changes nothing",
          "[control]") {
  Rig rig;
  rig.on_five(kPosition + R"("period_ms":10})");
  const std::string item = R"({"port":"dxl0","servo":1,"item":"present_position"})";
  std::string eleven;
  for (int i = 0; i < 11; ++i) {
    eleven += (i == 0 ? "" : ",") + item;
  }
  CHECK(rig.refused_on_five(R"({"cmd":"sample.subscribe","period_ms":10,"items":[)" + eleven +
                            "]}") == "\"items\" must hold 1 ~ 10 items, not 11");
  CHECK(rig.refused_on_five(R"({"cmd":"sample.subscribe","period_ms":10,"items":[]})") ==
        "\"items\" must hold 1 ~ 10 items, not 0");
  CHECK(rig.refused_on_five(R"({"cmd":"sample.subscribe","period_ms":10})") ==
        "\"items\" is required: a list of up to 10 items {\"port\"?, \"servo\", \"item\"}");
  CHECK(rig.refused_on_five(kPosition + R"("period_ms":0.5})") ==
        "\"period_ms\" must be 1 ~ 1000 (ms of simulated time), not 0.5");
  CHECK(rig.refused_on_five(kPosition + R"("period_ms":1001})") ==
        "\"period_ms\" must be 1 ~ 1000 (ms of simulated time), not 1001");
  CHECK(rig.refused_on_five(kPosition + R"("period_ms":"10"})") ==
        "\"period_ms\" must be a number");
  CHECK(rig.refused_on_five(R"({"cmd":"sample.subscribe","items":[)" + item + "]}") ==
        "\"period_ms\" is required: 1 ~ 1000 (ms of simulated time)");
  // Unknown ports, servos and items: the messages of get.
  const std::string start = R"({"cmd":"sample.subscribe","period_ms":10,"items":[)" + item + ",";
  CHECK(rig.refused_on_five(start + R"({"port":"dxl0","servo":1,"item":"goal_pos"}]})") ==
        rig.error(R"({"cmd":"get","port":"dxl0","servo":1,"item":"goal_pos"})"));
  CHECK(rig.refused_on_five(start + R"({"port":"dxl0","servo":9,"item":"id"}]})") ==
        "no servo 9 on dxl0 (servos: 1, 2)");
  CHECK(rig.refused_on_five(start + R"({"port":"dxl9","servo":1,"item":"id"}]})") ==
        "port \"dxl9\" does not exist (ports: dxl0, dxl1)");
  CHECK(rig.refused_on_five(start + R"({"servo":1,"item":"id"}]})") ==
        "\"port\" is required: there are 2 ports (dxl0, dxl1)");
  CHECK(rig.refused_on_five(start + R"({"port":"dxl0","servo":1}]})") ==
        "items[1]: \"item\" is required (an item's key, e.g. \"present_position\")");
  CHECK(rig.refused_on_five(start + R"({"port":"dxl0","servo":1,"item":"id","size":1}]})") ==
        "unknown field \"size\" in items[1] (an item takes port, servo, item)");
  CHECK(rig.refused_on_five(start + R"(3]})") ==
        "items[1] must be an object {\"port\"?, \"servo\", \"item\"}");
  CHECK(rig.error(kPosition + R"("period_ms":10})") ==
        "sample.subscribe needs a connection to send events to");
  CHECK(rig.error(R"({"cmd":"sample.unsubscribe"})") ==
        "sample.unsubscribe needs a connection to send events to");
  // The sampler running before the refusals goes on as it was.
  rig.step_ms(20);
  CHECK(rig.times() == std::vector<double>{0.01, 0.02});
  CHECK(rig.events[0]["values"].size() == 1);
}

TEST_CASE("sample.subscribe takes ten items, and periods of 1 and 1000 ms", "[control]") {
  Rig rig;
  std::string ten;
  for (int i = 0; i < 10; ++i) {
    ten += std::string(i == 0 ? "" : ",") + R"({"port":"dxl0","servo":2,"item":"id"})";
  }
  CHECK(rig.on_five(R"({"cmd":"sample.subscribe","period_ms":1,"items":[)" + ten + "]}")["items"]
            .size() == 10);
  rig.step_ms(3);
  REQUIRE(rig.events.size() == 3);
  CHECK(rig.events[2]["values"] == json::parse("[2,2,2,2,2,2,2,2,2,2]"));
  rig.events.clear();
  rig.on_five(kPosition + R"("period_ms":1000})");
  rig.step_ms(2500);
  CHECK(rig.times() == std::vector<double>{1.003, 2.003});
}

}  // namespace dxlemu::test::sample_commands
