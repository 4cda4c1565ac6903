// The physics seam without an engine (physics/world_clock.hpp): a hand-made world records what
// the clock does, so the order of a tick (every actuator's torque, then the steps, then every
// actuator's reading) and the tick arithmetic are checked in every build, MuJoCo or not.
#include <catch2/catch.hpp>

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/world_clock.hpp"

using namespace dxlemu;
using std::chrono::microseconds;
using std::chrono::milliseconds;

namespace {

// One joint, a unit inertia with no forces but the applied torque; every call is logged.
class LogWorld : public physics::World {
 public:
  explicit LogWorld(std::vector<std::string>& log, double dt = 0.001) : log_(log), dt_(dt) {}
  std::optional<std::size_t> find_joint(std::string_view name) const override {
    return name == "j" ? std::optional<std::size_t>(0) : std::nullopt;
  }
  std::vector<std::string> joints() const override { return {"j"}; }
  std::optional<std::size_t> find_body(std::string_view /*name*/) const override {
    return std::nullopt;
  }
  std::vector<std::string> bodies() const override { return {}; }
  double timestep_s() const override { return dt_; }
  void add_armature(std::size_t /*joint*/, double /*kg_m2*/) override {}
  void set_torque(std::size_t /*joint*/, double torque_nm) override {
    torque_ = torque_nm;
    log_.push_back("torque " + std::to_string(static_cast<int>(torque_nm)));
  }
  void set_external_torque(std::size_t /*joint*/, double /*torque_nm*/) override {}
  void set_wrench(std::size_t /*body*/, const physics::Wrench& /*wrench*/) override {}
  physics::Wrench wrench(std::size_t /*body*/) const override { return {}; }
  void step() override {
    velocity_ += torque_ * dt_;
    position_ += velocity_ * dt_;
    log_.emplace_back("step");
  }
  physics::JointState joint(std::size_t /*joint*/) const override { return {position_, velocity_}; }
  physics::JointForces forces(std::size_t /*joint*/) const override { return {torque_, 0, 0, 0}; }
  physics::Scene scene() const override { return {}; }
  std::vector<physics::GeomPose> geom_poses() override { return {}; }

 private:
  std::vector<std::string>& log_;
  double dt_;
  double torque_ = 0;
  double position_ = 0;
  double velocity_ = 0;
};

class LogActuator : public physics::JointActuator {
 public:
  LogActuator(std::vector<std::string>& log, int torque) : log_(log), torque_(torque) {}
  void drive(physics::World& world, sim::SimTime tick_end) override {
    log_.push_back("drive " + std::to_string(torque_) + " at " +
                   std::to_string(sim::ns_since_start(tick_end) / 1'000'000));
    world.set_torque(0, torque_);
  }
  void sense(const physics::World& /*world*/, sim::SimTime /*tick_end*/) override {
    log_.push_back("sense " + std::to_string(torque_));
  }

 private:
  std::vector<std::string>& log_;
  int torque_;
};

}  // namespace

TEST_CASE("A world tick sets every actuator's torque before the world steps and reads after",
          "[physics]") {
  std::vector<std::string> log;
  physics::WorldClock clock(std::make_unique<LogWorld>(log, 0.0005), milliseconds(1));
  LogActuator a(log, 1);
  LogActuator b(log, 2);
  clock.attach(a);
  clock.attach(b);
  REQUIRE(clock.substeps() == 2);
  clock.advance_to(sim::SimTime{} + microseconds(999));
  CHECK(log.empty());  // the first tick ends one period after the start
  clock.advance_to(sim::SimTime{} + milliseconds(2));
  const std::vector<std::string> expected{
      "drive 1 at 1", "torque 1", "drive 2 at 1", "torque 2", "step", "step", "sense 1", "sense 2",
      "drive 1 at 2", "torque 1", "drive 2 at 2", "torque 2", "step", "step", "sense 1", "sense 2"};
  CHECK(log == expected);
  CHECK(clock.ticks() == 2);
  // Catching up again to the same time runs nothing.
  clock.advance_to(sim::SimTime{} + milliseconds(2));
  CHECK(clock.ticks() == 2);
}

TEST_CASE("A detached actuator no longer takes part in the ticks", "[physics]") {
  std::vector<std::string> log;
  physics::WorldClock clock(std::make_unique<LogWorld>(log), milliseconds(1));
  LogActuator a(log, 1);
  clock.attach(a);
  clock.detach(a);
  clock.advance_to(sim::SimTime{} + milliseconds(1));
  const std::vector<std::string> expected{"step"};
  CHECK(log == expected);
}

TEST_CASE("A physics timestep that does not divide the motion tick is refused", "[physics]") {
  std::vector<std::string> log;
  CHECK_THROWS_AS(physics::WorldClock(std::make_unique<LogWorld>(log, 0.0003), milliseconds(1)),
                  std::invalid_argument);
  CHECK_THROWS_AS(physics::WorldClock(std::make_unique<LogWorld>(log, 0.002), milliseconds(1)),
                  std::invalid_argument);
  CHECK_NOTHROW(physics::WorldClock(std::make_unique<LogWorld>(log, 0.00025), milliseconds(1)));
}
