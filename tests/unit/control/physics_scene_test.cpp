// physics.scene (docs/control-api.md) on a hand-made world, in every build, MuJoCo or not: the
// reply's shape, and the world caught up to the request's time before its poses are read.
#include <catch2/catch.hpp>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "api_requests.hpp"
#include "control/api.hpp"
#include "physics/world_clock.hpp"
#include "ports_target.hpp"

using namespace dxlemu;
using nlohmann::json;

namespace dxlemu::test::physics_scene {

// No joints; one ball that moves 1 mm along x each step, and a plane that stays.
class BallWorld : public physics::World {
 public:
  std::optional<std::size_t> find_joint(std::string_view /*name*/) const override { return {}; }
  std::vector<std::string> joints() const override { return {}; }
  std::optional<std::size_t> find_body(std::string_view /*name*/) const override { return {}; }
  std::vector<std::string> bodies() const override { return {}; }
  double timestep_s() const override { return 0.001; }
  void add_armature(std::size_t /*joint*/, double /*kg_m2*/) override {}
  void set_torque(std::size_t /*joint*/, double /*torque_nm*/) override {}
  void set_external_torque(std::size_t /*joint*/, double /*torque_nm*/) override {}
  void set_wrench(std::size_t /*body*/, const physics::Wrench& /*wrench*/) override {}
  physics::Wrench wrench(std::size_t /*body*/) const override { return {}; }
  void step() override { ++steps_; }
  physics::JointState joint(std::size_t /*joint*/) const override { return {}; }
  physics::JointForces forces(std::size_t /*joint*/) const override { return {}; }
  physics::Scene scene() const override {
    return {{{"floor", "world", physics::GeomType::Plane, {1, 1, 0.1}, {0, 1, 0, 1}, ""},
             {"ball", "ball", physics::GeomType::Mesh, {0.5, 0.25, 0.125}, {1, 0, 0, 0.5}, "rock"}},
            {"mesh \"rock\" drawn as its bounding box"}};
  }
  std::vector<physics::GeomPose> geom_poses() override {
    const std::array<double, 9> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
    return {{{0, 0, 0}, identity}, {{0.001 * steps_, 0, 1}, identity}};
  }

 private:
  int steps_ = 0;
};

struct Rig : test::ApiRequests<Rig> {
  physics::WorldClock clock{std::make_unique<BallWorld>(), std::chrono::milliseconds(1)};
  control::PhysicsView view{clock, "ball.xml", {}};
  test::PortsTarget target;
  control::Api api{target};
  Rig() { target.world = &view; }
};

TEST_CASE("physics.scene lists each geom's shape, colour and pose, caught up to now",
          "[control][physics]") {
  Rig rig;
  rig.result(R"({"cmd":"clock.step","ms":250})");
  CHECK(rig.api.handle(R"({"id":1,"cmd":"physics.scene"})") ==
        R"({"id":1,"ok":true,"result":{"geoms":[)"
        R"({"name":"floor","body":"world","type":"plane","size":[1.0,1.0,0.1],)"
        R"("rgba":[0.0,1.0,0.0,1.0],"pos":[0.0,0.0,0.0],)"
        R"("mat":[1.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0,1.0]},)"
        R"({"name":"ball","body":"ball","type":"mesh","size":[0.5,0.25,0.125],)"
        R"("rgba":[1.0,0.0,0.0,0.5],"pos":[0.25,0.0,1.0],)"
        R"("mat":[1.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0,1.0],"mesh":"rock"}],)"
        R"("notes":["mesh \"rock\" drawn as its bounding box"]}})");
}

}  // namespace dxlemu::test::physics_scene
