// The command line (app/cli/command_line.*, docs/robots.md "Several robots in one daemon"): run's
// --robot is repeatable, and --physics and --hand belong to the --robot before them; before
// any --robot they belong to the only robot, or, with several, are refused.
#include <CLI/CLI.hpp>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "app/cli/command_line.hpp"

using namespace dxlemu;
using app::RobotRequest;

namespace command_line_test {

// The command line `dxlemu ARGS` as parsed by define_command_line.
struct Parsed {
  app::CommandLine line;
  std::string refusal;  ///< what CLI11 refused the command line with; empty when accepted
};

Parsed parse(std::vector<std::string> args) {
  Parsed parsed;
  CLI::App app{"dxlemu"};
  app::define_command_line(app, parsed.line);
  args.insert(args.begin(), "dxlemu");
  std::vector<char*> argv;
  argv.reserve(args.size());
  for (std::string& arg : args) {
    argv.push_back(arg.data());
  }
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    parsed.refusal = e.what();
  }
  return parsed;
}

}  // namespace command_line_test

TEST_CASE("Each --robot of run takes the --physics and --hand given after it", "[app][cli]") {
  const auto parsed = command_line_test::parse(
      {"run", "--robot", "so101-leader", "--hand", "sweep", "--robot", "so101-follower", "--timing",
       "fast", "--physics", "so101-follower", "--hand", "a", "--hand", "b"});
  REQUIRE(parsed.refusal.empty());
  CHECK(parsed.line.robots ==
        std::vector<RobotRequest>{{"so101-leader", std::nullopt, {"sweep"}},
                                  {"so101-follower", "so101-follower", {"a", "b"}}});
  CHECK(parsed.line.physics.empty());
  CHECK(parsed.line.hands.empty());
  CHECK(parsed.line.timing == "fast");
}

TEST_CASE("With one --robot, --physics and --hand before it are that robot's", "[app][cli]") {
  const auto parsed =
      command_line_test::parse({"run", "--hand", "h0", "--physics", "so101-follower", "--robot",
                                "so101-follower", "--hand", "h1"});
  REQUIRE(parsed.refusal.empty());
  CHECK(parsed.line.robots ==
        std::vector<RobotRequest>{{"so101-follower", "so101-follower", {"h0", "h1"}}});
  // The one robot of old command lines: --robot NAME --physics NAME, in either order.
  CHECK(command_line_test::parse({"run", "--robot", "a", "--physics", "p"}).line.robots ==
        std::vector<RobotRequest>{{"a", "p", {}}});
}

TEST_CASE("Without --robot, --physics and --hand are the bus's", "[app][cli]") {
  const auto config = command_line_test::parse(
      {"run", "--config", "arm.json", "--hand", "h", "--physics", "p", "--hand", "i"});
  REQUIRE(config.refusal.empty());
  CHECK(config.line.robots.empty());
  CHECK(config.line.physics == "p");
  CHECK(config.line.hands == std::vector<std::string>{"h", "i"});
  const auto servos = command_line_test::parse({"run", "--servo", "xm430-w350:1"});
  REQUIRE(servos.refusal.empty());
  CHECK(servos.line.physics.empty());
  CHECK(servos.line.hands.empty());
  // check's --physics is one value, as before.
  CHECK(command_line_test::parse({"check", "--robot", "a", "--physics", "p"}).line.physics == "p");
}

TEST_CASE("An option that belongs to no robot, or twice to one, is refused", "[app][cli]") {
  using command_line_test::parse;
  CHECK(parse({"run", "--physics", "p", "--robot", "a", "--robot", "b"}).refusal ==
        "--physics: given before the first --robot, with 2 robots: put it after the --robot it "
        "is for");
  CHECK(parse({"run", "--hand", "h", "--robot", "a", "--robot", "b"}).refusal ==
        "--hand: given before the first --robot, with 2 robots: put it after the --robot it is "
        "for");
  CHECK(parse({"run", "--robot", "a", "--physics", "p", "--physics", "q"}).refusal ==
        "--physics: given twice for robot a: one physics file per robot");
  CHECK(parse({"run", "--physics", "p", "--robot", "a", "--physics", "q"}).refusal ==
        "--physics: given twice for robot a: one physics file per robot");
  CHECK(parse({"run", "--servo", "xm430-w350:1", "--physics", "p", "--physics", "q"}).refusal ==
        "--physics: given twice: a daemon simulates one world");
  // One value per --robot; --robot still excludes --config and --servo.
  CHECK(parse({"run", "--robot", "a", "b"}).refusal ==
        "The following argument was not expected: b");
  CHECK(parse({"run", "--robot", "a", "--config", "c.json"}).refusal ==
        "--config excludes --robot");
  CHECK(parse({"run", "--servo", "xm430-w350:1", "--robot", "a"}).refusal ==
        "--servo excludes --robot");
}
