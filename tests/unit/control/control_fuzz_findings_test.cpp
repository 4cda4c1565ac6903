// Control API behaviours that fuzz_control (tests/fuzz/) found wrong, each reproduced with the
// request line the fuzzer's input boiled down to.
#include <catch2/catch.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

#include "control/api.hpp"
#include "control/target.hpp"

using namespace dxlemu;
using nlohmann::json;

namespace {

/// A Target with no ports: enough for requests refused before any command runs.
class EmptyTarget : public control::Target {
 public:
  std::vector<std::string> port_names() const override { return {}; }
  control::PortView* port(std::string_view /*name*/) override { return nullptr; }
  json port_info(std::string_view /*port*/) const override { return json::object(); }
  control::PhysicsView* physics() override { return nullptr; }
  std::shared_ptr<const model::Trajectory> trajectory(const std::string& file) override {
    throw std::invalid_argument(file + ": no trajectories here");
  }
  sim::SimTime now() const override { return {}; }
  bool manual_clock() const override { return true; }
  std::string_view timing() const override { return "manual"; }
  void step_clock(sim::SimDuration /*d*/) override {}
  faults::Injector& faults() override { return injector_; }
  void subscribe_trace(const control::Connection& /*connection*/,
                       std::vector<std::string> /*ports*/) override {}
  void unsubscribe_trace(std::uint64_t /*connection*/) override {}
  void schedule_in(sim::SimDuration /*delay*/, std::function<void()> /*action*/) override {}
  void warn(const std::string& /*message*/) override {}
  void request_shutdown() override {}

 private:
  faults::Injector injector_{1};
};

}  // namespace

TEST_CASE("A request with a number too large for a double gets an error reply", "[control][fuzz]") {
  // nlohmann::json reports "1e999" as out_of_range, not parse_error: it escaped Api::handle,
  // which never throws, and ended the daemon.
  EmptyTarget target;
  control::Api api(target);
  for (const std::string line :
       {R"({"id": 1e999, "cmd": "list"})", R"({"id": 1, "cmd": -6e666666})", "[66e333332]"}) {
    std::string reply;
    REQUIRE_NOTHROW(reply = api.handle(line));
    const json parsed = json::parse(reply);
    CHECK(parsed["id"].is_null());
    CHECK(parsed["ok"] == false);
    CHECK(parsed["error"].get<std::string>().starts_with("not valid JSON: number overflow"));
  }
}
