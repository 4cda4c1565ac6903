// Selecting Modbus RTU in configs, robot profiles and on the command line (docs/config.md
// "protocol"): the Protocol Type value it sets, the models that can speak it, its IDs 1 ~ 247.
#include <catch2/catch.hpp>

#include "app/config/bus_config.hpp"
#include "app/config/bus_options.hpp"
#include "shipped_models.hpp"

namespace dxlemu::test::modbus_config {

using Items = std::vector<std::pair<std::string, std::int64_t>>;

app::BusConfig parse(const std::string& servos) {
  return app::parse_config(R"({"ports":[{"name":"a","servos":[)" + servos + "]}]}", "bus.json",
                           shipped_models());
}

std::string refusal(const std::string& servos) {
  try {
    parse(servos);
  } catch (const app::ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

app::BusConfig one_port(std::vector<app::ServoConfig> servos) {
  app::BusConfig config;
  config.ports.push_back({"dxl0", std::nullopt, std::move(servos), {}, {}, {}, {}, {}});
  return config;
}

TEST_CASE("\"protocol\": \"modbus\" sets Protocol Type 10, and numbers and \"feetech\" as before",
          "[app][config][modbus]") {
  const auto config = parse(R"({"model": "ph42-020-s300-r", "ids": [1, 247], "protocol": "modbus"},
                               {"model": "ph54-200-s500-r", "id": 3, "protocol": 2})");
  REQUIRE(config.ports[0].servos.size() == 3);
  CHECK(config.ports[0].servos[0].items == Items{{"protocol_type", 10}});
  CHECK(config.ports[0].servos[1].id == 247);
  CHECK(config.ports[0].servos[2].items == Items{{"protocol_type", 2}});
  const auto spec = shipped_models().find("ph42-020-s300-r");
  CHECK(app::configured_protocol(config.ports[0].servos[0], *spec) == wire::Protocol::Modbus);
  CHECK(app::configured_protocol(config.ports[0].servos[2], *spec) == wire::Protocol::V2);
  CHECK(app::configured_protocol({"ph42-020-s300-r", 1, {}}, *spec) == wire::Protocol::V2);
  // FEETECH models have no Protocol Type: the shorthand names what they speak already.
  CHECK(parse(R"({"model": "sts3215", "id": 1, "protocol": "feetech"})").ports[0].servos[0].items ==
        Items{});
}

TEST_CASE("A model that cannot speak Modbus is refused naming the models that can",
          "[app][config][modbus]") {
  const std::string message = refusal(R"({"model": "xm430-w350", "id": 1, "protocol": "modbus"})");
  CHECK_THAT(message, Catch::StartsWith("bus.json: /ports/0/servos/0/protocol: xm430-w350 cannot "
                                        "speak Modbus RTU; the models that can: "));
  for (const char* name : {"ph42-020-s300-r", "ph54-100-s500-r", "ph54-200-s500-r",
                           "pm42-010-s260-r", "pm54-040-s250-r", "pm54-060-s250-r", "rh-p12-rna"}) {
    CHECK_THAT(message, Catch::Contains(name));
  }
  CHECK_THAT(message.substr(message.find("can: ")), !Catch::Contains("xm430"));
  // A long list is cut short, pointing at the full one.
  CHECK_THAT(refusal(R"({"model": "xl-320", "id": 1, "protocol": 1})"),
             Catch::Contains("more (dxlemu models --protocol 1)"));
  CHECK_THAT(refusal(R"({"model": "ph42-020-s300-r", "id": 1, "protocol": "Modbus"})"),
             Catch::Contains("\"Modbus\" is no protocol (known: 1, 2, \"feetech\", \"modbus\")"));
}

TEST_CASE("A Modbus servo's ID must be 1 ~ 247, from the shorthand or the item",
          "[app][config][modbus]") {
  CHECK(refusal(R"({"model": "ph42-020-s300-r", "id": 0, "protocol": "modbus"})") ==
        "bus.json: /ports/0/servos/0/id: servo ph42-020-s300-r:0 speaks Modbus RTU, whose IDs "
        "are 1 ~ 247");
  CHECK(
      refusal(R"({"model": "ph42-020-s300-r", "ids": [1, 248], "items": {"protocol_type": 10}})") ==
      "bus.json: /ports/0/servos/0/ids/1: servo ph42-020-s300-r:248 speaks Modbus RTU, whose "
      "IDs are 1 ~ 247");
  // The same IDs on 2.0 are fine, and an explicit Protocol Type 2 wins over the shorthand.
  CHECK(refusal(R"({"model": "ph42-020-s300-r", "ids": [0, 248]})") == "accepted");
  CHECK(refusal(R"({"model": "ph42-020-s300-r", "id": 0, "protocol": "modbus",
                    "items": {"protocol_type": 2}})") == "accepted");
}

TEST_CASE(
    "The option --protocol modbus sets Protocol Type 10, refusing models and IDs it cannot take",
    "[app][config][modbus]") {
  app::BusConfig config = one_port({{"ph42-020-s300-r", 1, {}}, {"rh-p12-rna", 2, {}}});
  app::apply_bus_options(config, shipped_models(), std::nullopt, wire::Protocol::Modbus);
  CHECK(config.ports[0].servos[0].items == Items{{"protocol_type", 10}});
  CHECK(config.ports[0].servos[1].items == Items{{"protocol_type", 10}});
  app::BusConfig xm = one_port({{"xm430-w350", 1, {}}});
  CHECK_THROWS_WITH(
      app::apply_bus_options(xm, shipped_models(), std::nullopt, wire::Protocol::Modbus),
      Catch::StartsWith("--protocol: xm430-w350 cannot speak Modbus RTU; the models that can: "
                        "ph42-020-s300-r"));
  app::BusConfig zero = one_port({{"ph42-020-s300-r", 0, {}}});
  CHECK_THROWS_WITH(
      app::apply_bus_options(zero, shipped_models(), std::nullopt, wire::Protocol::Modbus),
      "--protocol modbus: servo ph42-020-s300-r:0 speaks Modbus RTU, whose IDs are 1 ~ 247");
}

}  // namespace dxlemu::test::modbus_config
