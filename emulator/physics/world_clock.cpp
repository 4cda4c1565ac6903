#include "physics/world_clock.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dxlemu::physics {
namespace {

// A tick and a whole number of timesteps may differ by rounding of the timestep's double.
constexpr double kTickMatch = 1e-9;

std::int64_t substeps_of(const World& world, sim::SimDuration tick) {
  const double tick_s = std::chrono::duration<double>(tick).count();
  const double dt = world.timestep_s();
  if (!(dt > 0)) {
    throw std::invalid_argument("the physics timestep must be positive");
  }
  const double n = std::round(tick_s / dt);
  if (n < 1 || std::abs(n * dt - tick_s) > kTickMatch * tick_s) {
    throw std::invalid_argument("the physics timestep (" + std::to_string(dt * 1e3) +
                                " ms) must divide the motion tick (" +
                                std::to_string(tick_s * 1e3) + " ms) a whole number of times");
  }
  return static_cast<std::int64_t>(n);
}

}  // namespace

WorldClock::WorldClock(std::unique_ptr<World> world, sim::SimDuration tick)
    : world_(std::move(world)),
      tick_(tick),
      substeps_(substeps_of(*world_, tick)),
      next_tick_(sim::SimTime{} + tick) {}

void WorldClock::attach(JointActuator& actuator) {
  actuators_.push_back(&actuator);
}

void WorldClock::detach(JointActuator& actuator) {
  actuators_.erase(std::remove(actuators_.begin(), actuators_.end(), &actuator), actuators_.end());
}

void WorldClock::advance_to(sim::SimTime now) {
  // An actuator's drive() or sense() may reach code that catches its servo up: the tick under
  // way is that catch-up.
  if (stepping_) {
    return;
  }
  stepping_ = true;
  struct Unset {
    bool& flag;
    ~Unset() { flag = false; }
  } unset{stepping_};
  while (next_tick_ <= now) {
    // Every torque is set from the state at the start of the tick before the world moves, so no
    // servo sees another's torque of the same tick: the order of attachment does not matter.
    for (JointActuator* a : actuators_) {
      a->drive(*world_, next_tick_);
    }
    for (std::int64_t i = 0; i < substeps_; ++i) {
      world_->step();
    }
    for (JointActuator* a : actuators_) {
      a->sense(*world_, next_tick_);
    }
    next_tick_ += tick_;
    ++ticks_;
  }
}

}  // namespace dxlemu::physics
