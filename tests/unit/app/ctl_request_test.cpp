// `dxlemu ctl` (docs/control-api.md "From a shell: dxlemu ctl"): shell arguments to a request,
// a reply to what is printed, and which socket it talks to.
#include <catch2/catch.hpp>
#include <stdexcept>

#include "app/cli/ctl_request.hpp"
#include "live_sockets.hpp"

using namespace dxlemu;
using Args = std::vector<std::string>;

namespace {

using test::finding;

// The message ctl_request refuses `args` with.
std::string request_refusal(const Args& args) {
  try {
    app::ctl_request("set", args);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

std::string socket_refusal(const std::vector<std::filesystem::path>& live) {
  try {
    app::ctl_control_socket(std::nullopt, nullptr, "/run/user/1000", finding(live));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("key=value arguments become members, values read as JSON when they parse", "[app][ctl]") {
  CHECK(app::ctl_request("set", {"port=dxl0", "servo=3", "item=goal_position", "value=2048"})
            .dump() ==
        R"({"id":1,"cmd":"set","port":"dxl0","servo":3,"item":"goal_position","value":2048})");
  CHECK(app::ctl_request("condition.set", {"blocked=true", "supply_voltage=11.1", "name=\"3\""})
            .dump() == R"({"id":1,"cmd":"condition.set","blocked":true,"supply_voltage":11.1,)"
                       R"("name":"3"})");
  CHECK(app::ctl_request("x", {R"(rule={"action":"drop_reply"})", "empty=", "text=a=b"}).dump() ==
        R"({"id":1,"cmd":"x","rule":{"action":"drop_reply"},"empty":"","text":"a=b"})");
  CHECK(app::ctl_request("list", {}).dump() == R"({"id":1,"cmd":"list"})");
}

TEST_CASE("A JSON object argument has its members merged into the request", "[app][ctl]") {
  CHECK(app::ctl_request("get", {R"({"servo": 1, "item": "id"})", "port=dxl0"}).dump() ==
        R"({"id":1,"cmd":"get","servo":1,"item":"id","port":"dxl0"})");
}

TEST_CASE("Arguments that are not key=value, repeat a key or set id or cmd are refused",
          "[app][ctl]") {
  CHECK(request_refusal({"servo"}) == R"(argument "servo": expected key=value or a JSON object)");
  CHECK(request_refusal({"[1]"}) == R"(argument "[1]": expected key=value or a JSON object)");
  CHECK(request_refusal({"=3"}) == R"(argument "=3": the key before '=' is empty)");
  CHECK(request_refusal({"servo=1", R"({"servo":2})"}) ==
        R"(argument "{"servo":2}": "servo" is given twice)");
  CHECK(request_refusal({"cmd=get"}) ==
        R"(argument "cmd=get": "cmd" is set by dxlemu ctl (the command is the first argument))");
  CHECK(request_refusal({"id=4"}).find("\"id\" is set by dxlemu ctl") != std::string::npos);
}

TEST_CASE("A successful reply prints its result as indented JSON in the daemon's order",
          "[app][ctl]") {
  const auto outcome = app::ctl_outcome(R"({"id":1,"ok":true,"result":{"item":"id","value":1}})");
  CHECK(outcome.exit_code == 0);
  CHECK(outcome.out == "{\n  \"item\": \"id\",\n  \"value\": 1\n}\n");
  CHECK(outcome.err.empty());
  CHECK(app::ctl_outcome(R"({"id":1,"ok":true,"result":{}})").out == "{}\n");
}

TEST_CASE("A refused request prints the daemon's error and exits 1", "[app][ctl]") {
  const auto outcome = app::ctl_outcome(R"({"id":1,"ok":false,"error":"no servo 9 on dxl0"})");
  CHECK(outcome.exit_code == 1);
  CHECK(outcome.out.empty());
  CHECK(outcome.err == "dxlemu ctl: no servo 9 on dxl0\n");
  const auto garbled = app::ctl_outcome("hello");
  CHECK(garbled.exit_code == 1);
  CHECK(garbled.err == "dxlemu ctl: the daemon's reply is not a control API reply: hello\n");
}

TEST_CASE("The socket is --control, else DXLEMU_CONTROL, else the only live one", "[app][ctl]") {
  const auto never = [](const std::filesystem::path&) -> std::vector<std::filesystem::path> {
    throw std::logic_error("the directory must not be searched");
  };
  CHECK(app::ctl_control_socket("/tmp/a.sock", "/tmp/b.sock", "/tmp", never) == "/tmp/a.sock");
  CHECK(app::ctl_control_socket(std::nullopt, "/tmp/b.sock", "/tmp", never) == "/tmp/b.sock");
  CHECK(app::ctl_control_socket(std::nullopt, "", "/tmp", finding({"/tmp/dxlemu-7.sock"})) ==
        "/tmp/dxlemu-7.sock");
}

TEST_CASE("No live socket or several are refused, naming what was found", "[app][ctl]") {
  CHECK(socket_refusal({}) ==
        "no running dxlemu found: no live control socket /run/user/1000/dxlemu-*.sock; pass "
        "--control PATH (or set DXLEMU_CONTROL)");
  CHECK(socket_refusal({"/run/user/1000/dxlemu-1.sock", "/run/user/1000/dxlemu-2.sock"}) ==
        "several running dxlemu found (/run/user/1000/dxlemu-1.sock, "
        "/run/user/1000/dxlemu-2.sock); pass --control PATH (or set DXLEMU_CONTROL) to choose one");
}
