// The "physics" object of a bus config (docs/physics.md "Config"): what a valid one builds, that
// every mistake is refused with the file, the JSON pointer and the reason, and that a build
// without MuJoCo refuses it whole.
#include <catch2/catch.hpp>

#include <chrono>
#include <string>

#include "app/config/bus_config.hpp"
#include "app/config/physics_config.hpp"
#include "physics/mjcf_world.hpp"
#include "physics/physics_fixtures.hpp"
#include "shipped_models.hpp"

using namespace dxlemu;
using app::ConfigError;

namespace {

using test::kPendulum;

// A config of port "arm" with XM430-W350 ID 1 and `physics` as its physics object.
std::string with_physics(const std::string& physics) {
  return R"({"ports":[{"name":"arm","servos":[{"model":"xm430-w350","id":1}]}],"physics":)" +
         physics + "}";
}

std::string physics_refusal(const std::string& text) {
  try {
    app::parse_config(text, "bus.json", test::shipped_models());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

#ifdef DXLEMU_HAVE_MUJOCO

TEST_CASE("A physics object maps servos to joints with defaults for what it leaves out",
          "[app][config][physics]") {
  const auto config = app::parse_config(with_physics(R"({"mjcf": "p.xml", "joints": [
      {"port": "arm", "id": 1, "joint": "shoulder", "gear": 2.5, "direction": -1,
       "zero_offset_deg": 180}]})"),
                                        "bus.json", test::shipped_models());
  REQUIRE(config.physics);
  CHECK(config.physics->mjcf == "p.xml");
  CHECK_FALSE(config.physics->timestep_ms);
  CHECK(config.physics->origin == "bus.json");
  REQUIRE(config.physics->joints.size() == 1);
  CHECK(config.physics->joints[0] == app::JointConfig{"arm", 1, "shoulder", 2.5, -1, 180});
  const auto plain = app::parse_config(
      with_physics(
          R"({"mjcf":"p.xml","timestep_ms":0.5,"joints":[{"port":"arm","id":1,"joint":"j"}]})"),
      "bus.json", test::shipped_models());
  CHECK(plain.physics->timestep_ms == 0.5);
  CHECK(plain.physics->joints[0] == app::JointConfig{"arm", 1, "j", 1, 1, 0});
}

TEST_CASE("Every mistake in a physics object is refused with its pointer and reason",
          "[app][config][physics]") {
  const auto joint = [](const std::string& fields) {
    return with_physics(R"({"mjcf":"p.xml","joints":[{)" + fields + "}]}");
  };
  CHECK(physics_refusal(with_physics("[]")) == "bus.json: /physics: must be an object");
  CHECK(physics_refusal(with_physics(R"({"joints":[]})")) ==
        "bus.json: /physics/mjcf: is required");
  CHECK(physics_refusal(with_physics(R"({"mjcf":"p.xml","joints":[]})")) ==
        "bus.json: /physics/joints: must be a non-empty array of joints");
  CHECK(physics_refusal(with_physics(R"({"mjcf":"p.xml","step":1,"joints":[]})")) ==
        "bus.json: /physics/step: unknown field (allowed: mjcf, timestep_ms, joints, "
        "description)");
  CHECK(physics_refusal(with_physics(R"({"mjcf":"p.xml","timestep_ms":0,"joints":[]})")) ==
        "bus.json: /physics/timestep_ms: must be more than 0 and at most 100 ms");
  CHECK(physics_refusal(joint(R"("port":"leg","id":1,"joint":"j")")) ==
        "bus.json: /physics/joints/0/port: no port is called \"leg\"");
  CHECK(physics_refusal(joint(R"("port":"arm","id":2,"joint":"j")")) ==
        "bus.json: /physics/joints/0/id: port arm has no servo 2");
  CHECK(physics_refusal(joint(R"("port":"arm","id":1)")) ==
        "bus.json: /physics/joints/0/joint: is required");
  CHECK(physics_refusal(joint(R"("port":"arm","id":1,"joint":"j","gear":0)")) ==
        "bus.json: /physics/joints/0/gear: must be more than 0 (shaft turns per joint turn)");
  CHECK(physics_refusal(joint(R"("port":"arm","id":1,"joint":"j","direction":2)")) ==
        "bus.json: /physics/joints/0/direction: must be 1 or -1");
  CHECK(physics_refusal(joint(R"("port":"arm","id":1,"joint":"j","zero_offset_deg":"up")")) ==
        "bus.json: /physics/joints/0/zero_offset_deg: must be a number");
  CHECK(physics_refusal(with_physics(R"({"mjcf":"p.xml","joints":[
      {"port":"arm","id":1,"joint":"a"},{"port":"arm","id":1,"joint":"b"}]})")) ==
        "bus.json: /physics/joints/1: servo 1 of port arm already drives a joint");
}

TEST_CASE("An MJCF that does not load or lacks a joint is refused when the world is loaded",
          "[app][config][physics]") {
  app::PhysicsConfig config;
  config.origin = "bus.json";
  config.mjcf = std::string(DXLEMU_TEST_DATA_DIR) + "/physics/missing.xml";
  config.joints.push_back({"arm", 1, "elbow", 1, 1, 0});
  CHECK_THROWS_WITH(app::load_physics(config, std::chrono::milliseconds(1)),
                    Catch::StartsWith("bus.json: /physics/mjcf: " + config.mjcf.string() +
                                      ": MuJoCo cannot load it"));
  config.mjcf = kPendulum;
  const auto clock = app::load_physics(config, std::chrono::milliseconds(1));
  CHECK(clock->substeps() == 1);
  CHECK_THROWS_WITH(app::joint_mapping(config, 0, clock->world()),
                    "bus.json: /physics/joints/0/joint: " + kPendulum +
                        " has no hinge or slide joint \"elbow\" (its joints: shoulder)");
  config.timestep_ms = 0.3;
  CHECK_THROWS_WITH(app::load_physics(config, std::chrono::milliseconds(1)),
                    Catch::StartsWith("bus.json: /physics/timestep_ms: the physics timestep"));
}

TEST_CASE("The MJCF file of a config file is found beside it", "[app][config][physics]") {
  const auto config = app::read_config(std::string(DXLEMU_EXAMPLES_DIR) + "/physics/pendulum.json",
                                       test::shipped_models());
  REQUIRE(config.physics);
  CHECK(config.physics->mjcf == std::filesystem::path(kPendulum));
  CHECK(config.physics->joints[0] == app::JointConfig{"arm", 1, "shoulder", 1, 1, 180});
}

#else

TEST_CASE("A build without MuJoCo refuses a config asking for physics", "[app][config][physics]") {
  CHECK_FALSE(physics::mujoco_available());
  CHECK(physics_refusal(with_physics(R"({"mjcf":"p.xml","joints":[]})")) ==
        "bus.json: /physics: this build of dxlemu has no MuJoCo, so it cannot simulate physics "
        "(rebuild with Debian's libmujoco-dev installed and -DDXLEMU_MUJOCO=ON, "
        "docs/physics.md)");
  CHECK_THROWS_AS(physics::load_mjcf_world(kPendulum, 0.001), physics::PhysicsError);
}

#endif
