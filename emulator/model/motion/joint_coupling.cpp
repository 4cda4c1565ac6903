#include "model/motion/joint_coupling.hpp"

#include <numbers>

#include "model/motion/motion_model.hpp"

namespace dxlemu::model {
namespace {

// MotorParams::inertia is N·m per (pulse/ms²); kg·m² is N·m per (rad/s²).
constexpr double kMs2PerS2 = 1e6;
constexpr double kMsPerS = 1e3;

}  // namespace

JointCoupling::JointCoupling(MotionModel& motion, physics::WorldClock& clock,
                             const JointMapping& mapping)
    : motion_(motion), clock_(clock), mapping_(mapping) {
  const MotorParams& p = motion_.params();
  // The rotor through the servo's gearbox is the output-side inertia; through the coupling's
  // own gear it is seen gear² times at the joint.
  const double rotor_kg_m2 = p.inertia * pulses_per_rad() / kMs2PerS2;
  clock_.world().add_armature(mapping_.joint, rotor_kg_m2 * mapping_.gear * mapping_.gear);
  last_shaft_ = shaft_position();
  clock_.attach(*this);
}

JointCoupling::~JointCoupling() {
  clock_.detach(*this);
}

double JointCoupling::pulses_per_rad() const {
  return motion_.params().pulses_per_rev / (2 * std::numbers::pi);
}

double JointCoupling::shaft_position() const {
  const physics::JointState j = clock_.world().joint(mapping_.joint);
  return (mapping_.zero_offset_rad + mapping_.gear * mapping_.direction * j.position_rad) *
         motion_.params().pulses_per_rev / (2 * std::numbers::pi);
}

void JointCoupling::drive(physics::World& world, sim::SimTime tick_end) {
  // The motor first: its tick takes in device-side changes that may move the shaft the hand
  // then pushes.
  const double motor_torque = motion_.begin_coupled_tick(tick_end);
  const double shaft_torque =
      motor_torque + motion_.conditions().external_load_nm + motion_.coupled_hand_torque(tick_end);
  // Virtual work: a shaft torque τ through `gear` is gear·τ at the joint.
  world.set_torque(mapping_.joint, mapping_.gear * mapping_.direction * shaft_torque);
}

void JointCoupling::sense(const physics::World& world, sim::SimTime /*tick_end*/) {
  const physics::JointState j = world.joint(mapping_.joint);
  const double shaft = shaft_position();
  const double velocity =
      mapping_.gear * mapping_.direction * j.velocity_rad_s * pulses_per_rad() / kMsPerS;
  const double position = motion_.motor().position + (shaft - last_shaft_);
  last_shaft_ = shaft;
  motion_.end_coupled_tick(position, velocity);
}

}  // namespace dxlemu::model
