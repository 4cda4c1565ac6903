// Bus configs (docs/config.md): what a valid file builds, and that every mistake is refused with
// the file, the JSON pointer and the reason.
#include <catch2/catch.hpp>

#include "app/config/bus_config.hpp"
#include "shipped_models.hpp"

using namespace dxlemu;
using app::ConfigError;
using app::parse_config;

namespace {

app::BusConfig parse(const std::string& text) {
  return parse_config(text, "bus.json", test::shipped_models());
}

// The message parse_config refuses `text` with.
std::string config_refusal(const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

// A config of one port named a whose servo list is `servos`.
std::string one_port(const std::string& servos) {
  return R"({"ports":[{"name":"a","servos":[)" + servos + "]}]}";
}

}  // namespace

TEST_CASE("A config builds its ports in order, servos in bus order, with their overrides",
          "[app][config]") {
  const auto config = parse(R"({
    "description": "two arms",
    "ports": [
      {"name": "arm", "link": "/tmp/arm", "servos": [
        {"model": "xm430-w350", "ids": [3, 1], "items": {"return_delay_time": 0}},
        {"model": "ax-12a", "id": 7, "baud": 57600, "description": "gripper"}
      ]},
      {"name": "legs", "servos": []}
    ]})");
  REQUIRE(config.ports.size() == 2);
  const auto& arm = config.ports[0];
  CHECK(arm.name == "arm");
  CHECK(arm.link == std::filesystem::path("/tmp/arm"));
  REQUIRE(arm.servos.size() == 3);
  CHECK(arm.servos[0] == app::ServoConfig{"xm430-w350", 3, {{"return_delay_time", 0}}});
  CHECK(arm.servos[1] == app::ServoConfig{"xm430-w350", 1, {{"return_delay_time", 0}}});
  // AX-12A Baud Rate item value 34 is 57600 bps in its model file.
  CHECK(arm.servos[2].id == 7);
  CHECK(arm.servos[2].items ==
        std::vector<std::pair<std::string, std::int64_t>>{{"baud_rate", 34}});
  CHECK(config.ports[1].name == "legs");
  CHECK(!config.ports[1].link);
  CHECK(config.ports[1].servos.empty());
}

TEST_CASE("The protocol shorthand sets Protocol Type and an explicit item wins over a shorthand",
          "[app][config]") {
  const auto config = parse(one_port(
      R"({"model": "xm430-w350", "id": 1, "protocol": 1, "baud": 1000000,
          "items": {"baud_rate": 4}})"));
  CHECK(config.ports[0].servos[0].items ==
        std::vector<std::pair<std::string, std::int64_t>>{
            {"baud_rate", 3}, {"protocol_type", 1}, {"baud_rate", 4}});
}

TEST_CASE("A config names a firmware as the command line does, NAME@FIRMWARE", "[app][config]") {
  const auto config = parse(
      one_port(R"({"model": "xl330-m288@52", "id": 1, "items": {"indirect_address_20": 132}})"));
  REQUIRE(config.ports[0].servos.size() == 1);
  CHECK(config.ports[0].servos[0].model == "xl330-m288@52");
  const auto spec = test::shipped_models().find("xl330-m288@52");
  REQUIRE(spec != nullptr);
  CHECK(spec->firmware_version == 52);
  CHECK(spec->find("indirect_data_1")->address == 208);
  // The default firmware by its number is the model itself; the variants are listed by name.
  CHECK(test::shipped_models().find("xl330-m288@53") == test::shipped_models().find("xl330-m288"));
  const auto variants = test::shipped_models().variants_of("xl330-m288");
  REQUIRE(variants.size() == 1);
  CHECK(variants[0]->name == "xl330-m288@52");
  CHECK(test::shipped_models().variants_of("xm335-t323").empty());
  // Indirect Address 21 exists only from V53.
  CHECK_THAT(config_refusal(one_port(
                 R"({"model": "xl330-m288@52", "id": 1, "items": {"indirect_address_21": 132}})")),
             Catch::Contains("xl330-m288@52 has no item \"indirect_address_21\""));
}

TEST_CASE("Every mistake in a config is refused naming the file, the JSON pointer and the reason",
          "[app][config]") {
  using Case = std::pair<std::string, std::string>;
  const std::vector<Case> cases = {
      {"{", "bus.json: /: not valid JSON"},
      {"[]", "bus.json: /: must be an object"},
      {R"({"ports": []})", "bus.json: /ports: must be a non-empty array of ports"},
      {R"({"ports": [{"name": "a", "servos": []}], "port": 1})",
       "bus.json: /port: unknown field (allowed: ports, robot, physics, description)"},
      {R"({"ports": [{"servos": []}]})", "bus.json: /ports/0/name: is required"},
      {R"({"ports": [{"name": "a b", "servos": []}]})",
       "bus.json: /ports/0/name: must be 1 to 32 letters"},
      {R"({"ports": [{"name": "a", "servos": []}, {"name": "a", "servos": []}]})",
       "bus.json: /ports/1/name: port name \"a\" is used twice"},
      {R"({"ports": [{"name": "a", "link": "/tmp/x", "servos": []},
                     {"name": "b", "link": "/tmp//x", "servos": []}]})",
       "bus.json: /ports/1/link: link /tmp//x is used twice"},
      {R"({"ports": [{"name": "a", "link": 3, "servos": []}]})",
       "bus.json: /ports/0/link: must be a non-empty string"},
      {R"({"ports": [{"name": "a", "servos": {}}]})",
       "bus.json: /ports/0/servos: must be an array of servos"},
      {one_port(R"({"model": "xm999", "id": 1})"),
       "bus.json: /ports/0/servos/0/model: unknown model \"xm999\""},
      {one_port(R"({"model": "xl330-m288@51", "id": 1})"),
       "bus.json: /ports/0/servos/0/model: xl330-m288 has no firmware \"51\" (known: 53, 52)"},
      {one_port(R"({"model": "xm335-t323@52", "id": 1})"),
       "bus.json: /ports/0/servos/0/model: xm335-t323 has no firmware \"52\" (known: 46)"},
      {one_port(R"({"model": "xm430-w350"})"),
       "bus.json: /ports/0/servos/0: needs exactly one of \"id\" and \"ids\""},
      {one_port(R"({"model": "xm430-w350", "id": 1, "ids": [2]})"),
       "bus.json: /ports/0/servos/0: needs exactly one of \"id\" and \"ids\""},
      {one_port(R"({"model": "xm430-w350", "id": 253})"),
       "bus.json: /ports/0/servos/0/id: 253 is outside 0 ~ 252"},
      {one_port(R"({"model": "xm430-w350", "id": "1"})"),
       "bus.json: /ports/0/servos/0/id: must be an integer"},
      {one_port(R"({"model": "xm430-w350", "ids": [1, -1]})"),
       "bus.json: /ports/0/servos/0/ids/1: -1 is outside 0 ~ 252"},
      {one_port(R"({"model": "xm430-w350", "ids": []})"),
       "bus.json: /ports/0/servos/0/ids: must be a non-empty array of IDs"},
      {one_port(R"({"model": "ax-12a", "id": 1, "baud": 4500000})"),
       "bus.json: /ports/0/servos/0/baud: ax-12a cannot do 4500000 bps (it offers 1000000"},
      {one_port(R"({"model": "xl-320", "id": 1, "protocol": 1})"),
       "bus.json: /ports/0/servos/0/protocol: xl-320 cannot speak Protocol 1.0; the models that "
       "can: "},
      {one_port(R"({"model": "xm430-w350", "id": 1, "protocol": 3})"),
       "bus.json: /ports/0/servos/0/protocol: 3 is no protocol (known: 1, 2, \"feetech\", "
       "\"modbus\")"},
      {one_port(R"({"model": "xm430-w350", "id": 1, "protocol": "2"})"),
       "bus.json: /ports/0/servos/0/protocol: \"2\" is no protocol"},
      {one_port(R"({"model": "xm430-w350", "id": 1, "items": {"speed": 3}})"),
       "bus.json: /ports/0/servos/0/items/speed: xm430-w350 has no item \"speed\""},
      {one_port(R"({"model": "xm430-w350", "id": 1, "items": {"a/b~": 3}})"),
       "bus.json: /ports/0/servos/0/items/a~1b~0: xm430-w350 has no item \"a/b~\""},
      {one_port(R"({"model": "xm430-w350", "id": 1, "items": {"model_number": 3}})"),
       "bus.json: /ports/0/servos/0/items/model_number: xm430-w350 model_number is read-only"},
      {one_port(R"({"model": "xm430-w350", "id": 1, "items": {"return_delay_time": 300}})"),
       "bus.json: /ports/0/servos/0/items/return_delay_time: xm430-w350 return_delay_time 300 "
       "is outside its range 0 ~ 254"},
      {one_port(R"({"model": "xm430-w350", "id": 1, "items": {"id": 1.5}})"),
       "bus.json: /ports/0/servos/0/items/id: must be an integer"},
      {one_port(R"({"model": "xm430-w350", "id": 1, "colour": "red"})"),
       "bus.json: /ports/0/servos/0/colour: unknown field"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    CHECK_THAT(config_refusal(text), Catch::StartsWith(message));
  }
}

TEST_CASE("An unreadable config file is refused naming it", "[app][config]") {
  try {
    app::read_config("/nonexistent/bus.json", test::shipped_models());
    FAIL("accepted");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()) == "/nonexistent/bus.json: /: cannot be read");
  }
}

TEST_CASE("A port may set its USB adapter's latency timer and chip", "[app][config]") {
  const app::BusConfig config = parse(R"({"ports": [
      {"name": "a", "adapter_latency_ms": 16, "adapter_chip": "ft232r", "servos": []},
      {"name": "b", "adapter_latency_ms": 0, "servos": []},
      {"name": "c", "servos": []}]})");
  REQUIRE(config.ports.size() == 3);
  CHECK(config.ports[0].adapter_latency_ms == 16);
  CHECK(config.ports[0].adapter_chip == "ft232r");
  CHECK(config.ports[1].adapter_latency_ms == 0);  // none here, whatever the command line says
  CHECK_FALSE(config.ports[1].adapter_chip);
  CHECK_FALSE(config.ports[2].adapter_latency_ms);  // the command line's
  CHECK(app::adapter_packet_data("ft232h") == 510);
  CHECK(app::adapter_packet_data("ft232r") == 62);
  CHECK_FALSE(app::adapter_packet_data("ch340"));
}

TEST_CASE("A bad USB adapter setting is refused naming the file and the JSON pointer",
          "[app][config]") {
  using Case = std::pair<std::string, std::string>;
  const std::vector<Case> cases = {
      {R"({"ports": [{"name": "a", "adapter_latency_ms": 256, "servos": []}]})",
       "bus.json: /ports/0/adapter_latency_ms: 256 is outside 0 ~ 255"},
      {R"({"ports": [{"name": "a", "adapter_latency_ms": -1, "servos": []}]})",
       "bus.json: /ports/0/adapter_latency_ms: -1 is outside 0 ~ 255"},
      {R"({"ports": [{"name": "a", "adapter_latency_ms": 1.5, "servos": []}]})",
       "bus.json: /ports/0/adapter_latency_ms: must be an integer"},
      {R"({"ports": [{"name": "a", "adapter_chip": "ch340", "servos": []}]})",
       "bus.json: /ports/0/adapter_chip: unknown chip \"ch340\" (known: ft232h, ft232r)"},
      {R"({"ports": [{"name": "a", "adapter_chip": 232, "servos": []}]})",
       "bus.json: /ports/0/adapter_chip: must be a non-empty string"},
      {R"({"ports": [{"name": "a", "adapter": 16, "servos": []}]})",
       "bus.json: /ports/0/adapter: unknown field (allowed: name, link, servos, "
       "adapter_latency_ms, adapter_chip, joints, hand, description)"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    CHECK(config_refusal(text) == message);
  }
}

TEST_CASE("The library loads FEETECH's catalog, model numbers are one maker's",
          "[app][config][feetech]") {
  for (const std::string name : {"sts3215", "sts3250", "sm8512bl", "scs0009", "hls3625m"}) {
    INFO(name);
    const auto spec = test::shipped_models().find(name);
    REQUIRE(spec);
    CHECK(spec->protocols == std::vector{wire::Protocol::Feetech});
  }
  CHECK(test::shipped_models().find(777, model::Maker::Feetech) ==
        test::shipped_models().find("sts3215"));
  CHECK(test::shipped_models().find(777, model::Maker::Robotis) == nullptr);
  CHECK(test::shipped_models().find(1020, model::Maker::Robotis) ==
        test::shipped_models().find("xm430-w350"));
  CHECK(test::shipped_models().find(1020, model::Maker::Feetech) == nullptr);
  app::ModelFilter feetech;
  feetech.protocol = wire::Protocol::Feetech;
  CHECK(test::shipped_models().select(feetech).size() == 5);
}

TEST_CASE("A port of FEETECH servos parses, one mixing makers is refused",
          "[app][config][feetech]") {
  const auto config = parse(one_port(R"({"model": "sts3215", "ids": [1, 2, 3], "baud": 1000000})"));
  REQUIRE(config.ports[0].servos.size() == 3);
  CHECK(config.ports[0].servos[0].items ==
        std::vector<std::pair<std::string, std::int64_t>>{{"baud_rate", 0}});
  CHECK(config_refusal(one_port(R"({"model": "xm430-w350", "ids": [1, 2]},
                            {"model": "sts3215", "id": 3})")) ==
        "bus.json: /ports/0/servos/1: sts3215 is a FEETECH model, but xm430-w350 on the same "
        "port is ROBOTIS: a port speaks one maker's protocol (put them on separate ports)");
  CHECK_THAT(config_refusal(one_port(R"({"model": "sts3215", "id": 1, "protocol": 1})")),
             Catch::StartsWith("bus.json: /ports/0/servos/0/protocol: sts3215 cannot speak "
                               "Protocol 1.0; the models that can: "));
}

namespace bus_config_joints_test {

// A port "arm" of three XM430-W350 at IDs 1 to 3 whose "joints" member is `joints`.
std::string arm_with_joints(const std::string& joints) {
  return R"({"ports":[{"name":"arm","servos":[{"model":"xm430-w350","ids":[1,2,3]}],"joints":)" +
         joints + "}]}";
}

}  // namespace bus_config_joints_test

TEST_CASE("A port names its servos' joints, with a range where one is given", "[app][config]") {
  using bus_config_joints_test::arm_with_joints;
  const auto config = parse(arm_with_joints(R"([
      {"name": "shoulder_pan", "id": 2, "range_deg": [-110, 110.5]},
      {"name": "Wrist-2.roll", "id": 1, "description": "no range"}])"));
  REQUIRE(config.ports.size() == 1);
  CHECK(config.ports.front().joints ==
        std::vector<app::JointName>{{"shoulder_pan", 2, std::pair{-110.0, 110.5}},
                                    {"Wrist-2.roll", 1, std::nullopt}});
  // A plain config's port belongs to no robot; a port need not name its joints.
  CHECK(config.ports.front().robot.empty());
  CHECK(parse(one_port(R"({"model": "xm430-w350", "id": 1})")).ports.front().joints.empty());
  // Eight turns either way is the widest range.
  CHECK(parse(arm_with_joints(R"([{"name": "spin", "id": 3, "range_deg": [-2880, 2880]}])"))
            .ports.front()
            .joints.front()
            .range_deg == std::pair{-2880.0, 2880.0});
}

TEST_CASE("A bad joint is refused naming the file, the JSON pointer and the reason",
          "[app][config]") {
  using bus_config_joints_test::arm_with_joints;
  using Case = std::pair<std::string, std::string>;
  const std::string a = R"({"name": "a", "id": 1})";
  const std::vector<Case> cases = {
      {arm_with_joints("{}"), "bus.json: /ports/0/joints: must be an array of joints"},
      {arm_with_joints("[1]"), "bus.json: /ports/0/joints/0: must be an object"},
      {arm_with_joints(R"([{"id": 1}])"), "bus.json: /ports/0/joints/0/name: is required"},
      {arm_with_joints(R"([{"name": "a"}])"), "bus.json: /ports/0/joints/0/id: is required"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "gear": 2}])"),
       "bus.json: /ports/0/joints/0/gear: unknown field (allowed: name, id, range_deg, "
       "description)"},
      {arm_with_joints(R"([{"name": "", "id": 1}])"),
       "bus.json: /ports/0/joints/0/name: must be a non-empty string"},
      {arm_with_joints(R"([{"name": "elbow flex", "id": 1}])"),
       "bus.json: /ports/0/joints/0/name: must be 1 to 40 letters, digits, '_', '-' or '.'"},
      {arm_with_joints(R"([{"name": ")" + std::string(41, 'j') + R"(", "id": 1}])"),
       "bus.json: /ports/0/joints/0/name: must be 1 to 40 letters, digits, '_', '-' or '.'"},
      {arm_with_joints(R"([{"name": "12", "id": 1}])"),
       "bus.json: /ports/0/joints/0/name: must not be all digits (a number names a servo by "
       "its ID)"},
      {arm_with_joints("[" + a + R"(, {"name": "a", "id": 2}])"),
       "bus.json: /ports/0/joints/1/name: joint name \"a\" is used twice on this port"},
      {arm_with_joints("[" + a + R"(, {"name": "b", "id": 1}])"),
       "bus.json: /ports/0/joints/1/id: servo 1 is joint \"a\" already: one joint per servo"},
      {arm_with_joints(R"([{"name": "a", "id": 4}])"),
       "bus.json: /ports/0/joints/0/id: port arm has no servo 4"},
      {arm_with_joints(R"([{"name": "a", "id": 253}])"),
       "bus.json: /ports/0/joints/0/id: 253 is outside 0 ~ 252"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": 90}])"),
       "bus.json: /ports/0/joints/0/range_deg: must be [low, high] in degrees"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": [1, 2, 3]}])"),
       "bus.json: /ports/0/joints/0/range_deg: must be [low, high] in degrees"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": [-90, "90"]}])"),
       "bus.json: /ports/0/joints/0/range_deg/1: must be a number"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": [-2881, 0]}])"),
       "bus.json: /ports/0/joints/0/range_deg/0: -2881 is outside -2880 ~ 2880 degrees (8 turns "
       "either way)"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": [10, -10]}])"),
       "bus.json: /ports/0/joints/0/range_deg: low 10 must be less than high -10"},
      {arm_with_joints(R"([{"name": "a", "id": 1, "range_deg": [5.5, 5.5]}])"),
       "bus.json: /ports/0/joints/0/range_deg: low 5.5 must be less than high 5.5"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    CHECK(config_refusal(text) == message);
  }
}
