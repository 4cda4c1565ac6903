// Robot profiles (docs/robots.md): every shipped profile loads and cites its source, a bad header
// or a misnamed profile is refused with the file, the JSON pointer and the reason, and --robot's
// bus is the profile's with --link on its one port.
#include <catch2/catch.hpp>
#include <filesystem>

#include "app/config/robot_library.hpp"
#include "physics/mjcf_world.hpp"

using namespace dxlemu;
using app::ConfigError;

namespace {

namespace fs = std::filesystem;

const app::ModelLibrary& models() {
  static const app::ModelLibrary lib = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  return lib;
}

const app::RobotLibrary& shipped() {
  static const app::RobotLibrary lib = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {}, models());
  return lib;
}

// The message parse_config refuses `text` with, as file robot.json.
std::string profile_refusal(const std::string& text) {
  try {
    app::parse_config(text, "robot.json", models());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

// A profile of one XM430-W350 at ID 1 whose robot header is `header`.
std::string with_header(const std::string& header) {
  return R"({"robot":)" + header +
         R"(, "ports":[{"name":"arm","servos":[{"model":"xm430-w350","id":1}]}]})";
}

}  // namespace

TEST_CASE("Every shipped robot profile loads under its file name and cites a public source",
          "[app][robots]") {
  std::size_t files = 0;
  for (const auto& f : fs::directory_iterator(DXLEMU_ROBOTS_DIR)) {
    files += f.path().extension() == ".json" ? 1 : 0;
  }
  REQUIRE(files > 0);
  CHECK(shipped().profiles().size() == files);
  for (const auto& [name, profile] : shipped().profiles()) {
    INFO(profile.file.string());
    CHECK(profile.file.stem().string() == name);
    CHECK(profile.header().name == name);
    CHECK_FALSE(profile.header().title.empty());
    REQUIRE_FALSE(profile.header().sources.empty());
    CHECK(profile.header().sources.front().rfind("https://", 0) == 0);
    CHECK_FALSE(profile.header().notes.empty());
    CHECK_FALSE(profile.config.ports.empty());
  }
}

TEST_CASE("The SO-101 follower profile is six STS3215 at 1 Mbit/s on one port", "[app][robots]") {
  const app::RobotProfile* so101 = shipped().find("so101-follower");
  REQUIRE(so101 != nullptr);
  REQUIRE(so101->config.ports.size() == 1);
  const auto& servos = so101->config.ports.front().servos;
  REQUIRE(servos.size() == 6);
  for (std::size_t i = 0; i < servos.size(); ++i) {
    CHECK(servos[i].model == "sts3215");
    CHECK(servos[i].id == i + 1);
    // STS3215 Baud Rate value 0 is 1,000,000 bps in its model file.
    CHECK(servos[i].items == std::vector<std::pair<std::string, std::int64_t>>{{"baud_rate", 0}});
  }
}

TEST_CASE("A robot header is parsed into the config and a plain config has none", "[app][robots]") {
  const auto config = app::parse_config(
      with_header(R"({"name":"arm-1","title":"An arm","sources":["https://example.org/a.yaml"],
                      "software":"a driver","notes":"one paragraph"})"),
      "arm-1.json", models());
  REQUIRE(config.robot);
  CHECK(*config.robot == app::RobotHeader{"arm-1",
                                          "An arm",
                                          {"https://example.org/a.yaml"},
                                          "a driver",
                                          {"one paragraph"},
                                          {},
                                          {}});
  CHECK_FALSE(
      app::parse_config(R"({"ports":[{"name":"a","servos":[]}]})", "bus.json", models()).robot);
}

TEST_CASE("A bad robot header is refused naming the file, the JSON pointer and the reason",
          "[app][robots]") {
  const std::string source = R"("sources":["https://example.org/a.yaml"])";
  CHECK(profile_refusal(with_header("[]")) == "robot.json: /robot: must be an object");
  CHECK(profile_refusal(with_header(R"({"title":"t",)" + source + "}")) ==
        "robot.json: /robot/name: is required");
  CHECK(profile_refusal(with_header(R"({"name":"Arm","title":"t",)" + source + "}")) ==
        "robot.json: /robot/name: must be 1 to 40 lowercase letters, digits, '_', '.' or '-', "
        "not starting with '.'");
  CHECK(profile_refusal(with_header(R"({"name":"a","title":"t","sources":[]})")) ==
        "robot.json: /robot/sources: must be a non-empty array of strings");
  CHECK(profile_refusal(with_header(R"({"name":"a","title":"t","sources":["wx250.yaml"]})")) ==
        "robot.json: /robot/sources/0: must be a URL (https://...) of the public file the facts "
        "come from");
  CHECK(profile_refusal(with_header(R"({"name":"a","title":"t",)" + source + R"(,"notes":[1]})")) ==
        "robot.json: /robot/notes/0: must be a non-empty string");
  CHECK(profile_refusal(with_header(R"({"name":"a","title":"t",)" + source + R"(,"baud":1})")) ==
        "robot.json: /robot/baud: unknown field (allowed: name, title, sources, software, notes, "
        "role, pairs_with, description)");
}

TEST_CASE("A profile whose header names another file, or without a header, is refused",
          "[app][robots]") {
  const fs::path bad = fs::path(DXLEMU_TEST_DATA_DIR) / "bad_robots";
  try {
    app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {bad}, models());
    FAIL("accepted");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()) ==
          (bad / "wrong-name.json").string() +
              ": /robot/name: \"another-name\" must be the file's name, \"wrong-name\"");
  }
  // A plain config among the profiles: the shipped docs/examples/robot.json has no header.
  const fs::path examples =
      fs::path(DXLEMU_TEST_DATA_DIR).parent_path().parent_path() / "docs" / "examples";
  try {
    app::RobotLibrary::load("/nonexistent", {examples}, models());
    FAIL("accepted");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()).find("robot.json: /robot: is required in a robot profile") !=
          std::string::npos);
  }
}

TEST_CASE("A profile served with --robot is its bus, and --link replaces its one port's link",
          "[app][robots]") {
  const auto bus = app::robot_bus(shipped(), "openmanipulator-x", std::nullopt);
  CHECK(bus == shipped().find("openmanipulator-x")->config);
  const auto linked = app::robot_bus(shipped(), "openmanipulator-x", fs::path("/tmp/omx"));
  CHECK(linked.ports.front().link == fs::path("/tmp/omx"));
  CHECK(linked.ports.front().servos == bus.ports.front().servos);
  try {
    app::robot_bus(shipped(), "no-such-robot", std::nullopt);
    FAIL("accepted");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.rfind("--robot: unknown robot \"no-such-robot\" (known: ", 0) == 0);
    CHECK(message.find("so101-follower") != std::string::npos);
  }
}

TEST_CASE("A profile of several ports refuses --link, naming them", "[app][robots]") {
  const fs::path dir = fs::path(DXLEMU_TEST_DATA_DIR) / "robots_two_ports";
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {dir}, models());
  CHECK(robots.profiles().size() == shipped().profiles().size() + 1);
  CHECK(app::robot_bus(robots, "two-ports", std::nullopt).ports.size() == 2);
  try {
    app::robot_bus(robots, "two-ports", fs::path("/tmp/x"));
    FAIL("accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()) == "--link: robot two-ports has 2 ports (arm, gripper); copy " +
                                       (dir / "two-ports.json").string() +
                                       " and set each port's link there");
  }
}

TEST_CASE("A physics file is named by its path or by its name beside the profiles, and attached",
          "[app][robots][physics]") {
  const fs::path dir = fs::path(DXLEMU_TEST_DATA_DIR) / "robots_physics";
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {dir}, models());
  const fs::path file = dir / "physics" / "pendulum-arm.json";
  CHECK(robots.physics_file("pendulum-arm") == file);
  CHECK(robots.physics_file(file.string()) == file);
  CHECK(*robots.find_physics("pendulum-arm") == file);
  try {
    robots.physics_file("no-such-arm");
    FAIL("accepted");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.rfind("--physics: no-such-arm is no file, nor a shipped physics model (known: ",
                        0) == 0);
    CHECK(message.find("pendulum-arm") != std::string::npos);
  }

  app::BusConfig config =
      app::parse_config(with_header(R"({"name":"arm","title":"t",)"
                                    R"("sources":["https://x"],"notes":["n"]})"),
                        "arm.json", models());
  if (!physics::mujoco_available()) {
    try {
      app::attach_physics(config, file);
      FAIL("accepted");
    } catch (const ConfigError& e) {
      // The whole file is what is refused: pointer "", which errors print as "/".
      CHECK(std::string(e.what()) == file.string() +
                                         ": /: this build of dxlemu has no MuJoCo, so it cannot "
                                         "simulate physics (rebuild with Debian's libmujoco-dev "
                                         "installed and -DDXLEMU_MUJOCO=ON, docs/physics.md)");
    }
    return;
  }
  app::BusConfig attached = config;
  app::attach_physics(attached, file);
  REQUIRE(attached.physics);
  CHECK(attached.physics->mjcf ==
        file.parent_path() / "../../../../docs/examples/physics/pendulum.xml");
  CHECK(attached.physics->pointer.empty());
  CHECK(attached.physics->joints ==
        std::vector<app::JointConfig>{{"arm", 1, "shoulder", 1, 1, 180}});
  // Errors name the physics file and pointers within it.
  try {
    app::attach_physics(config, dir / "physics" / "no-servo-2.json");
    FAIL("accepted");
  } catch (const ConfigError& e) {
    CHECK(std::string(e.what()) == (dir / "physics" / "no-servo-2.json").string() +
                                       ": /joints/0/id: port arm has no servo 2");
  }
  try {
    app::attach_physics(attached, file);
    FAIL("accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()) ==
          "--physics: the config has a \"physics\" of its own (" + file.string() + ")");
  }
}
