#pragma once

#include <cstddef>

#include "physics/joint_actuator.hpp"
#include "physics/world_clock.hpp"

namespace dxlemu::model {

class MotionModel;

/// How a servo's output shaft meets a joint of the physics world.
struct JointMapping {
  /// The world's joint (World::find_joint).
  std::size_t joint = 0;
  /// Shaft turns per joint turn (a gear or belt between the horn and the joint; 1: direct).
  double gear = 1;
  /// 1: the shaft's positive direction (towards higher positions, before Drive Mode and Homing
  /// Offset) turns the joint positively; -1: the other way.
  double direction = 1;
  /// The shaft's angle when the joint is at 0, rad (π: an X-series servo reads 2048 there).
  double zero_offset_rad = 0;
};

/// A servo's motion model acting on one joint of a WorldClock's world (docs/physics.md). Each
/// tick: the motor's torque (MotorPhysics::drive, through the gear) plus the servo's external
/// load and a hand's push goes onto the joint; after the world's steps the shaft follows the joint
/// and the servo runs its protection and publishes its Present values. The motor's rotor inertia,
/// seen through the gear, is added to the joint. Made by MotionModel::couple(); detaches itself
/// when destroyed.
class JointCoupling : public physics::JointActuator {
 public:
  JointCoupling(MotionModel& motion, physics::WorldClock& clock, const JointMapping& mapping);
  ~JointCoupling() override;
  JointCoupling(const JointCoupling&) = delete;
  JointCoupling& operator=(const JointCoupling&) = delete;

  void drive(physics::World& world, sim::SimTime tick_end) override;
  void sense(const physics::World& world, sim::SimTime tick_end) override;

  physics::WorldClock& clock() { return clock_; }
  const JointMapping& mapping() const { return mapping_; }
  /// The shaft's angle for the joint's state now, pulses (before direction and Homing Offset).
  double shaft_position() const;

 private:
  double pulses_per_rad() const;

  MotionModel& motion_;
  physics::WorldClock& clock_;
  JointMapping mapping_;
  // The shaft angle the world gave at the last sense(): the motor's position moves by the
  // world's increments, so that turns the servo drops (one turn at torque on, Clear) stay
  // dropped.
  double last_shaft_ = 0;
};

}  // namespace dxlemu::model
