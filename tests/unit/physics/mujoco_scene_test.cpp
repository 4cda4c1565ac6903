// What MuJoCo's world tells a drawing of it (physics::World::scene and geom_poses): every geom's
// shape, colour and pose now, a mesh as its bounding box. Built only with MuJoCo.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <string>

#include "physics/mujoco_world.hpp"
#include "temp_dir.hpp"

using namespace dxlemu;
using physics::GeomType;

namespace dxlemu::test::mujoco_scene {

// A floor, a height field, a 0.2 x 0.4 x 0.6 m block mesh (corner at its origin) placed at x = 1,
// and an arm hanging from a hinge at 1 m: a red rod along its x and a box at the rod's end.
constexpr const char* kScene = R"(<mujoco model="scene">
  <option timestep="0.001"/>
  <asset>
    <material name="red" rgba="1 0 0 1"/>
    <mesh name="block" vertex="0 0 0  0.2 0 0  0 0.4 0  0.2 0.4 0  0 0 0.6  0.2 0 0.6  0 0.4 0.6  0.2 0.4 0.6"/>
    <hfield name="bumps" nrow="2" ncol="2" size="1 1 0.1 0.1"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1" rgba="0 1 0 1"/>
    <geom name="ground" type="hfield" hfield="bumps"/>
    <geom name="block" type="mesh" mesh="block" pos="1 0 0"/>
    <body name="arm" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0.1 0 0" size="0.01" material="red"/>
      <geom type="box" size="0.01 0.02 0.03" pos="0.1 0 0"/>
    </body>
  </worldbody>
</mujoco>
)";

struct SceneFile {
  test::TempDir dir{"dxlemu-scene"};
  std::filesystem::path path = dir.path() / "scene.xml";
  SceneFile() { std::ofstream(path) << kScene; }
};

// MuJoCo parses the sizes as decimal text: equal to the double nearest, or very near it.
bool near(const std::array<double, 3>& got, const std::array<double, 3>& want) {
  for (std::size_t i = 0; i < 3; ++i) {
    if (got[i] != Approx(want[i])) {
      return false;
    }
  }
  return true;
}

// Column `c` of a row-major 3x3 rotation: where the geom's local axis c points.
std::array<double, 3> axis(const physics::GeomPose& pose, std::size_t c) {
  return {pose.mat[c], pose.mat[3 + c], pose.mat[6 + c]};
}

TEST_CASE("A MuJoCo world describes its geoms for drawing, a mesh as its bounding box",
          "[physics][mujoco]") {
  const SceneFile file;
  physics::MujocoWorld world(file.path, 0.001);
  const physics::Scene scene = world.scene();
  REQUIRE(scene.geoms.size() == 4);
  CHECK(scene.notes ==
        std::vector<std::string>{"geom \"ground\" left out: a height field is not drawn",
                                 "mesh \"block\" drawn as its bounding box"});

  const physics::GeomShape& floor = scene.geoms[0];
  CHECK(floor.name == "floor");
  CHECK(floor.body == "world");
  CHECK(floor.type == GeomType::Plane);
  CHECK(near(floor.size, {2, 2, 0.1}));
  CHECK(floor.rgba == std::array<double, 4>{0, 1, 0, 1});

  const physics::GeomShape& block = scene.geoms[1];
  CHECK(block.type == GeomType::Mesh);
  CHECK(block.mesh == "block");
  CHECK(block.rgba == std::array<double, 4>{0.5, 0.5, 0.5, 1});  // MuJoCo's default

  const physics::GeomShape& rod = scene.geoms[2];
  CHECK(rod.name == "rod");
  CHECK(rod.body == "arm");
  CHECK(rod.type == GeomType::Capsule);
  CHECK(rod.size[0] == Approx(0.01));
  CHECK(rod.size[1] == Approx(0.05));  // half the length between the caps' centres
  CHECK(rod.rgba == std::array<double, 4>{1, 0, 0, 1});  // its material's

  const physics::GeomShape& box = scene.geoms[3];
  CHECK(box.name.empty());
  CHECK(box.type == GeomType::Box);
  CHECK(near(box.size, {0.01, 0.02, 0.03}));

  const std::vector<physics::GeomPose> poses = world.geom_poses();
  REQUIRE(poses.size() == 4);
  // The mesh's box is centred on the block, and its extents along the world's axes are the
  // block's, however MuJoCo turned the mesh's frame (its principal axes of inertia).
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(poses[1].pos[i] == Approx(std::array<double, 3>{1.1, 0.2, 0.3}[i]));
    double extent = 0;
    for (std::size_t j = 0; j < 3; ++j) {
      extent += std::abs(poses[1].mat[3 * i + j]) * block.size[j];
    }
    CHECK(extent == Approx(std::array<double, 3>{0.1, 0.2, 0.3}[i]));
  }
  // The capsule lies along its local z: the rod's x.
  CHECK(poses[2].pos[0] == Approx(0.05));
  CHECK(poses[2].pos[2] == Approx(1));
  CHECK(std::abs(axis(poses[2], 2)[0]) == Approx(1));
}

TEST_CASE("Geom poses are those of the state now, not of the last step's start",
          "[physics][mujoco]") {
  const SceneFile file;
  physics::MujocoWorld world(file.path, 0.001);
  const std::size_t hinge = world.find_joint("hinge").value();
  for (int i = 0; i < 300; ++i) {
    world.step();  // the arm falls from level
  }
  const double angle = world.joint(hinge).position_rad;
  REQUIRE(angle > 0.1);
  const physics::GeomPose box = world.geom_poses()[3];
  // About +y, a positive angle turns the arm's x towards -z.
  CHECK(box.pos[0] == Approx(0.1 * std::cos(angle)).epsilon(1e-9));
  CHECK(box.pos[2] == Approx(1 - 0.1 * std::sin(angle)).epsilon(1e-9));
  CHECK(axis(box, 0)[0] == Approx(std::cos(angle)).epsilon(1e-9));
  CHECK(axis(box, 0)[2] == Approx(-std::sin(angle)).epsilon(1e-9));
  // Asking changes nothing of what follows: the same steps from a fresh world end the same.
  physics::MujocoWorld again(file.path, 0.001);
  for (int i = 0; i < 301; ++i) {
    again.step();
  }
  world.step();
  CHECK(world.joint(hinge).position_rad == again.joint(hinge).position_rad);
  CHECK(world.joint(hinge).velocity_rad_s == again.joint(hinge).velocity_rad_s);
}

}  // namespace dxlemu::test::mujoco_scene
