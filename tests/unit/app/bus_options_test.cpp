// `dxlemu run`'s --servo, --baud and --protocol as a bus config (README.md "Running the emulator").
#include <catch2/catch.hpp>

#include "app/config/bus_options.hpp"
#include "shipped_models.hpp"

using namespace dxlemu;
using app::parse_servo_option;

namespace {

// The message parse_servo_option refuses `text` with.
std::string servo_refusal(const std::string& text) {
  try {
    parse_servo_option(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

// One port of `servos`, with nothing overridden.
app::BusConfig one_port(std::vector<app::ServoConfig> servos) {
  app::BusConfig config;
  config.ports.push_back({"dxl0", std::nullopt, std::move(servos), {}, {}, {}, {}, {}});
  return config;
}

using Items = std::vector<std::pair<std::string, std::int64_t>>;

}  // namespace

TEST_CASE("A --servo of NAME:ID is one servo, NAME:FIRST-LAST one per ID", "[app][config]") {
  CHECK(parse_servo_option("xm430-w350:7") == std::vector<app::ServoConfig>{{"xm430-w350", 7, {}}});
  CHECK(parse_servo_option("ex-106+:1-3") == std::vector<app::ServoConfig>{
                                                 {"ex-106+", 1, {}},
                                                 {"ex-106+", 2, {}},
                                                 {"ex-106+", 3, {}},
                                             });
  // The firmware stays in the name, for the library to resolve.
  CHECK(parse_servo_option("xl330-m288@52:0-0").front().model == "xl330-m288@52");
  CHECK(parse_servo_option("ax-12a:252").front().id == 252);
}

TEST_CASE("A malformed --servo is refused naming the option", "[app][config]") {
  CHECK(servo_refusal("xm430-w350") == "--servo xm430-w350: expected NAME:ID or NAME:FIRST-LAST");
  CHECK(servo_refusal(":1") == "--servo :1: expected NAME:ID or NAME:FIRST-LAST");
  CHECK(servo_refusal("xm430-w350:one") ==
        "--servo xm430-w350:one: the ID part must be a number or FIRST-LAST");
  CHECK(servo_refusal("xm430-w350:1x") ==
        "--servo xm430-w350:1x: the ID part must be a number or FIRST-LAST");
  CHECK(servo_refusal("xm430-w350:1-2x") ==
        "--servo xm430-w350:1-2x: the ID part must be a number or FIRST-LAST");
  CHECK(servo_refusal("xm430-w350:3-1") ==
        "--servo xm430-w350:3-1: IDs must lie in 0 ~ 252, first <= last");
  CHECK(servo_refusal("xm430-w350:1-253") ==
        "--servo xm430-w350:1-253: IDs must lie in 0 ~ 252, first <= last");
}

TEST_CASE("The --baud and --protocol items come after a servo's own overrides", "[app][config]") {
  app::BusConfig config = one_port({{"xm430-w350", 1, {{"return_delay_time", 0}}}});
  app::apply_bus_options(config, test::shipped_models(), 1000000, wire::Protocol::V1);
  // Baud Rate 3 is 1 Mbps and Protocol Type 1 is DYNAMIXEL 1.0 in the XM430's model file.
  CHECK(config.ports[0].servos[0].items ==
        Items{{"return_delay_time", 0}, {"baud_rate", 3}, {"protocol_type", 1}});
}

TEST_CASE("Without --baud or --protocol a config stays as it is", "[app][config]") {
  app::BusConfig config = one_port({{"xm430-w350", 1, {{"led", 1}}}});
  const app::BusConfig before = config;
  app::apply_bus_options(config, test::shipped_models(), std::nullopt, std::nullopt);
  CHECK(config == before);
}

TEST_CASE("A --baud or --protocol a model cannot do is refused naming the options",
          "[app][config]") {
  app::BusConfig config = one_port({{"xm430-w350", 1, {}}});
  CHECK_THROWS_WITH(app::apply_bus_options(config, test::shipped_models(), 1234, std::nullopt),
                    Catch::StartsWith("--baud: xm430-w350 cannot do 1234 bps"));
  CHECK_THROWS_WITH(
      app::apply_bus_options(config, test::shipped_models(), 1234, wire::Protocol::V2),
      Catch::StartsWith("--baud/--protocol: xm430-w350 cannot do 1234 bps"));
  app::BusConfig ax = one_port({{"ax-12a", 1, {}}});
  CHECK_THROWS_WITH(
      app::apply_bus_options(ax, test::shipped_models(), std::nullopt, wire::Protocol::V2),
      Catch::StartsWith("--protocol: ax-12a cannot speak Protocol 2.0; the models that can: "));
}

TEST_CASE("A servo of an unknown model is left for check_servo to name", "[app][config]") {
  app::BusConfig config = one_port({{"no-such-servo", 1, {}}});
  app::apply_bus_options(config, test::shipped_models(), 1000000, wire::Protocol::V2);
  CHECK(config.ports[0].servos[0].items.empty());
}
