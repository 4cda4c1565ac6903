#pragma once

#include "physics/world.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::physics {

/// Something that drives a joint of a World once per tick: a servo's motor. The WorldClock calls
/// every actuator's drive() for a tick, then steps the world, then calls every actuator's
/// sense(), so all of them act on the same world state and see the same result.
class JointActuator {
 public:
  virtual ~JointActuator() = default;
  /// The tick ending at `tick_end` (simulated time) is about to run: set the torques.
  virtual void drive(World& world, sim::SimTime tick_end) = 0;
  /// The world has stepped through the tick: read the joints back.
  virtual void sense(const World& world, sim::SimTime tick_end) = 0;
};

}  // namespace dxlemu::physics
