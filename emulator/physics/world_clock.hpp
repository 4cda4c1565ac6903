#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "physics/joint_actuator.hpp"
#include "physics/world.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::physics {

/// Steps one World on dxlemu's virtual clock for every actuator attached to it (all servos of a
/// config that share the world, across ports). Ticks are at whole multiples of the tick period,
/// as the servos' own; each tick runs every actuator's drive(), then the world's steps that fill
/// the tick, then every actuator's sense(). Lazy like the motion model: advance_to() catches up
/// on every tick due, whoever calls it first.
class WorldClock {
 public:
  /// Steps `world` in ticks of `tick`; the tick must be a whole number of the world's timesteps
  /// (std::invalid_argument otherwise).
  WorldClock(std::unique_ptr<World> world, sim::SimDuration tick);

  /// Adds an actuator; it must outlive the clock or be detached first.
  void attach(JointActuator& actuator);
  void detach(JointActuator& actuator);

  /// Runs every tick due up to `now` (simulated time). A call made from inside a tick (an
  /// actuator catching up) does nothing.
  void advance_to(sim::SimTime now);

  World& world() { return *world_; }
  const World& world() const { return *world_; }
  sim::SimDuration tick() const { return tick_; }
  /// World steps per tick.
  std::int64_t substeps() const { return substeps_; }
  /// Ticks run so far.
  std::int64_t ticks() const { return ticks_; }

 private:
  std::unique_ptr<World> world_;
  sim::SimDuration tick_;
  std::int64_t substeps_;
  sim::SimTime next_tick_;
  std::int64_t ticks_ = 0;
  bool stepping_ = false;
  std::vector<JointActuator*> actuators_;
};

}  // namespace dxlemu::physics
