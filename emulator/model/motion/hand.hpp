#pragma once

#include <optional>

#include "sim/sim_time.hpp"

namespace dxlemu::model {

/// How hard a hand pushes unless told otherwise, N·m at the output shaft: a firm grip on a
/// servo horn, more than the small servos of a leader arm hold (docs/hands.md "A hand meets
/// torque").
inline constexpr double kDefaultHandForceNm = 2.0;

/// Where a hand holds a servo's shaft at one moment, and how hard it may push (docs/hands.md).
struct Grip {
  /// The shaft angle the hand holds, pulses as MotorState::position counts them (Present
  /// Position at factory settings: no Homing Offset, normal direction). An angle, not a count
  /// of turns: the hand takes the shaft the short way round to it, so whole turns are made by
  /// moving through them.
  double position = 0;
  /// How fast the hand moves there, pulses/ms.
  double velocity = 0;
  /// The most torque the hand puts on the shaft, N·m at the output.
  double force_limit_nm = kDefaultHandForceNm;

  bool operator==(const Grip&) const = default;
};

/// Something outside a servo that moves its shaft as a person's hand does: a trajectory played
/// back, a sweep through the joint's range, a move to one place. A torque-off shaft follows it
/// exactly; a torque-on one feels it as an external load up to its force limit (docs/hands.md).
/// Times are simulated.
class Hand {
 public:
  virtual ~Hand() = default;

  /// Where the hand holds the shaft at `t`; nullopt when it does not hold it (it has let go).
  virtual std::optional<Grip> grip(sim::SimTime t) const = 0;

  /// True when grip(t') equals grip(t) for every t' from `t` on: the hand holds still, so a
  /// shaft at rest in it may rest too (the motion model then skips its ticks).
  virtual bool still_from(sim::SimTime t) const = 0;
};

}  // namespace dxlemu::model
