// Robot profiles (docs/robots.md): every shipped profile loads and cites its source, a bad header
// or a misnamed profile is refused with the file, the JSON pointer and the reason, and --robot's
// bus is the profile's with --link on its one port.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "app/config/robot_library.hpp"
#include "physics/mjcf_world.hpp"
#include "temp_dir.hpp"

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

namespace robot_pairs_test {

// A profile NAME of one port "arm" with an XM430-W350 at ID 1 and the header members `extra`
// (e.g. R"("role": "leader")"), its port's link `link` when not empty.
std::string profile(const std::string& name, const std::string& extra,
                    const std::string& link = "") {
  return R"({"robot": {"name": ")" + name + R"(", "title": "t", "sources": ["https://x"])" +
         (extra.empty() ? "" : ", " + extra) + R"(}, "ports": [{"name": "arm", )" +
         (link.empty() ? "" : R"("link": ")" + link + R"(", )") +
         R"("servos": [{"model": "xm430-w350", "id": 1}]}]})";
}

// Writes `text` to DIR/NAME.json.
void write(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / (name + ".json")) << text;
}

// What RobotLibrary::load refuses the shipped profiles and `dir` with.
std::string load_refusal(const fs::path& dir) {
  try {
    app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {dir}, models());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

// What robots_bus refuses `requests` of `robots` with.
std::string merge_refusal(const app::RobotLibrary& robots,
                          const std::vector<app::RobotRequest>& requests,
                          const std::optional<fs::path>& link = std::nullopt) {
  try {
    app::robots_bus(robots, requests, link);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace robot_pairs_test

TEST_CASE("Every shipped profile names its joints as its software does, each a servo of its port",
          "[app][robots]") {
  const std::vector<std::string> lerobot = {"shoulder_pan", "shoulder_lift", "elbow_flex",
                                            "wrist_flex",   "wrist_roll",    "gripper"};
  const std::map<std::string, std::vector<std::string>> names = {
      {"so101-follower", lerobot},
      {"so101-leader", lerobot},
      {"koch-v1.1-follower", lerobot},
      {"koch-v1.1-leader", lerobot},
      {"openmanipulator-x", {"joint1", "joint2", "joint3", "joint4", "gripper"}},
      {"openmanipulator-y", {"joint1", "joint2", "joint3", "joint4", "joint5", "joint6"}},
      {"widowx-250", {"waist", "shoulder", "elbow", "wrist_angle", "wrist_rotate", "gripper"}},
      {"poppy-ergo-jr", {"m1", "m2", "m3", "m4", "m5", "m6"}},
  };
  for (const auto& [name, profile] : shipped().profiles()) {
    INFO(name);
    REQUIRE(profile.config.ports.size() == 1);
    const app::PortConfig& port = profile.config.ports.front();
    CHECK(port.robot == name);
    std::vector<std::string> joints;
    for (const app::JointName& joint : port.joints) {
      joints.push_back(joint.name);
      if (joint.range_deg) {
        // Within a turn either way of the middle of the servo's range, never a point.
        CHECK(joint.range_deg->first < joint.range_deg->second);
        CHECK(joint.range_deg->first >= -180);
        CHECK(joint.range_deg->second <= 180);
      }
    }
    REQUIRE(names.count(name) == 1);
    CHECK(joints == names.at(name));
  }
  // WidowX-250's shadows (3 and 5) move with their masters: no joints of their own.
  std::set<int> widowx_ids;
  for (const app::JointName& joint : shipped().find("widowx-250")->config.ports.front().joints) {
    widowx_ids.insert(joint.id);
  }
  CHECK(widowx_ids == std::set<int>{1, 2, 4, 6, 7, 8});
  // The SO-101's ranges are its MJCF's, joint 0 at position 2048.
  const auto& so101 = shipped().find("so101-follower")->config.ports.front().joints;
  CHECK(so101.front().range_deg == std::pair{-110.0, 110.0});
  CHECK(so101.at(4).range_deg == std::pair{-157.21, 162.79});
}

TEST_CASE("The shipped leaders and followers pair up: SO-101's and Koch's", "[app][robots]") {
  CHECK(shipped().pairs() ==
        std::vector<std::pair<std::string, std::string>>{{"koch-v1.1-leader", "koch-v1.1-follower"},
                                                         {"so101-leader", "so101-follower"}});
  const app::RobotHeader& leader = shipped().find("so101-leader")->header();
  CHECK(leader.role == app::RobotRole::Leader);
  CHECK(leader.pairs_with == "so101-follower");
  CHECK(shipped().find("so101-follower")->header().role == app::RobotRole::Follower);
  CHECK_FALSE(shipped().find("widowx-250")->header().role);
}

TEST_CASE("A role or pair that does not hold is refused naming the file and the JSON pointer",
          "[app][robots]") {
  using robot_pairs_test::load_refusal;
  using robot_pairs_test::profile;
  using robot_pairs_test::write;
  CHECK(profile_refusal(profile("a", R"("role": "boss")")) ==
        "robot.json: /robot/role: must be \"leader\" or \"follower\"");
  CHECK(profile_refusal(profile("a", R"("pairs_with": "b")")) ==
        "robot.json: /robot/pairs_with: needs \"role\": a pair is a leader and a follower");
  CHECK(profile_refusal(profile("a", R"("role": "leader", "pairs_with": "a")")) ==
        "robot.json: /robot/pairs_with: must name another robot's profile, not this one");
  CHECK(profile_refusal(profile("a", R"("role": "leader", "pairs_with": "B")")) ==
        "robot.json: /robot/pairs_with: must be 1 to 40 lowercase letters, digits, '_', '.' or "
        "'-', not starting with '.'");
  // A role alone is fine.
  CHECK(profile_refusal(profile("a", R"("role": "follower")")) == "accepted");

  test::TempDir dir("dxlemu-pairs");
  const std::string a_file = (dir.path() / "a.json").string();
  const std::string b_file = (dir.path() / "b.json").string();
  write(dir.path(), "a", profile("a", R"("role": "leader", "pairs_with": "b")"));
  CHECK_THAT(load_refusal(dir.path()),
             Catch::StartsWith(a_file + ": /robot/pairs_with: unknown robot \"b\" (known: a, "));
  write(dir.path(), "b", profile("b", ""));
  CHECK(load_refusal(dir.path()) ==
        a_file + ": /robot/pairs_with: b (" + b_file +
            ") is neither leader nor follower: a leader pairs with a follower");
  write(dir.path(), "b", profile("b", R"("role": "leader")"));
  CHECK(load_refusal(dir.path()) == a_file + ": /robot/pairs_with: b (" + b_file +
                                        ") is a leader: a leader pairs with a follower");
  write(dir.path(), "b", profile("b", R"("role": "follower")"));
  CHECK(load_refusal(dir.path()) == a_file + ": /robot/pairs_with: b (" + b_file +
                                        ") must name a back in its \"pairs_with\" (it names none)");
  write(dir.path(), "b", profile("b", R"("role": "follower", "pairs_with": "a")"));
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {dir.path()}, models());
  CHECK(robots.pairs().front() == std::pair<std::string, std::string>{"a", "b"});

  // A follower naming a shipped leader that names another: refused from the follower's side.
  test::TempDir other("dxlemu-pairs");
  write(other.path(), "b", profile("b", R"("role": "follower", "pairs_with": "so101-leader")"));
  CHECK(load_refusal(other.path()) ==
        (other.path() / "b.json").string() + ": /robot/pairs_with: so101-leader (" +
            (fs::path(DXLEMU_ROBOTS_DIR) / "so101-leader.json").string() +
            ") must name b back in its \"pairs_with\" (it names so101-follower)");
}

TEST_CASE("Several robots are one bus: ports in order, each named by its robot", "[app][robots]") {
  const auto pair = app::robots_bus(
      shipped(), {{"so101-leader", {}, {}}, {"so101-follower", {}, {}}}, std::nullopt);
  REQUIRE(pair.ports.size() == 2);
  CHECK_FALSE(pair.robot);
  CHECK_FALSE(pair.physics);
  for (std::size_t i = 0; i < pair.ports.size(); ++i) {
    const std::string name = i == 0 ? "so101-leader" : "so101-follower";
    const app::PortConfig& profile_port = shipped().find(name)->config.ports.front();
    app::PortConfig expected = profile_port;
    expected.name = name;  // the profile's "arm"
    CHECK(pair.ports[i] == expected);
    CHECK(pair.ports[i].robot == name);
    CHECK(pair.ports[i].link == profile_port.link);
  }
  CHECK(app::served_port_name("so101-leader", "arm", 1) == "so101-leader");
  CHECK(app::served_port_name("two-ports", "gripper", 2) == "two-ports.gripper");

  // A profile of several ports: ROBOT.PORT.
  const fs::path two = fs::path(DXLEMU_TEST_DATA_DIR) / "robots_two_ports";
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {two}, models());
  const auto merged =
      app::robots_bus(robots, {{"two-ports", {}, {}}, {"widowx-250", {}, {}}}, std::nullopt);
  std::vector<std::string> names;
  for (const app::PortConfig& port : merged.ports) {
    names.push_back(port.name);
  }
  CHECK(names == std::vector<std::string>{"two-ports.arm", "two-ports.gripper", "widowx-250"});

  // One robot keeps its profile's names, as before.
  CHECK(app::robots_bus(shipped(), {{"so101-follower", {}, {}}}, std::nullopt) ==
        shipped().find("so101-follower")->config);
  CHECK(app::robots_bus(shipped(), {{"so101-follower", {}, {}}}, fs::path("/tmp/f"))
            .ports.front()
            .link == fs::path("/tmp/f"));
}

TEST_CASE("Robots that cannot share a daemon are refused, naming what clashes", "[app][robots]") {
  using robot_pairs_test::merge_refusal;
  using robot_pairs_test::profile;
  using robot_pairs_test::write;
  CHECK(merge_refusal(shipped(), {{"so101-leader", {}, {}}, {"so101-leader", {}, {}}}) ==
        "--robot: so101-leader is given twice; one daemon serves a robot once");
  CHECK(merge_refusal(shipped(), {{"so101-leader", {}, {}}, {"so101-follower", {}, {}}},
                      fs::path("/tmp/x")) ==
        "--link: several robots are served (so101-leader, so101-follower), each on the links of "
        "its profile; copy a profile to change its links");
  CHECK_THAT(merge_refusal(shipped(), {{"so101-leader", {}, {}}, {"nope", {}, {}}}),
             Catch::StartsWith("--robot: unknown robot \"nope\""));

  test::TempDir dir("dxlemu-merge");
  write(dir.path(), "copy", profile("copy", "", "/tmp//dxlemu-so101-follower"));
  // "a.b" of one port and port "b" of "a" would both be "a.b".
  write(dir.path(), "a.b", profile("a.b", ""));
  write(dir.path(), "a",
        R"({"robot": {"name": "a", "title": "t", "sources": ["https://x"]}, "ports": [
              {"name": "b", "servos": [{"model": "xm430-w350", "id": 1}]},
              {"name": "c", "servos": [{"model": "xm430-w350", "id": 2}]}]})");
  const std::string long_name(30, 'l');
  write(dir.path(), long_name,
        R"({"robot": {"name": ")" + long_name + R"(", "title": "t", "sources": ["https://x"]},
            "ports": [{"name": "arm", "servos": [{"model": "xm430-w350", "id": 1}]},
                      {"name": "hand", "servos": [{"model": "xm430-w350", "id": 2}]}]})");
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {dir.path()}, models());
  CHECK(merge_refusal(robots, {{"so101-follower", {}, {}}, {"copy", {}, {}}}) ==
        "--robot: port arm of so101-follower and port arm of copy have the same link "
        "/tmp//dxlemu-so101-follower; copy one profile and give its port another link");
  CHECK(merge_refusal(robots, {{"a", {}, {}}, {"a.b", {}, {}}}) ==
        "--robot: port b of a and port arm of a.b would both be called \"a.b\"");
  CHECK(merge_refusal(robots, {{long_name, {}, {}}, {"a.b", {}, {}}}) ==
        "--robot: port arm of " + long_name + " would be called \"" + long_name +
            ".arm\", longer than a port name's 32 characters; copy the profile under a shorter "
            "name");
}

TEST_CASE("Physics belongs to one robot of several, its joints on that robot's renamed ports",
          "[app][robots][physics]") {
  using robot_pairs_test::merge_refusal;
  const std::vector<app::RobotRequest> requests = {{"so101-leader", {}, {}},
                                                   {"so101-follower", "so101-follower", {}}};
  if (!physics::mujoco_available()) {
    // The physics file is refused whole: this build has no MuJoCo.
    try {
      app::robots_bus(shipped(), requests, std::nullopt);
      FAIL("accepted");
    } catch (const ConfigError& e) {
      CHECK_THAT(e.what(), Catch::Contains("so101-follower.json: /: this build of dxlemu has no "
                                           "MuJoCo"));
    }
    return;
  }
  const auto merged = app::robots_bus(shipped(), requests, std::nullopt);
  REQUIRE(merged.physics);
  REQUIRE(merged.physics->joints.size() == 6);
  for (const app::JointConfig& joint : merged.physics->joints) {
    CHECK(joint.port == "so101-follower");
  }
  CHECK(merge_refusal(shipped(), {{"so101-follower", "so101-follower", {}},
                                  {"openmanipulator-x", "openmanipulator-x", {}}}) ==
        "--physics: so101-follower and openmanipulator-x both have physics, and a daemon "
        "simulates one world; serve one of them with a second dxlemu run");
  // The physics file is read against the robot's own ports: a leader has no physics file of its
  // own, and the follower's names port "arm", which the leader also has before renaming.
  const auto leader_physics = app::robots_bus(
      shipped(), {{"so101-leader", "so101-follower", {}}, {"so101-follower", {}, {}}},
      std::nullopt);
  REQUIRE(leader_physics.physics);
  CHECK(leader_physics.physics->joints.front().port == "so101-leader");
}
