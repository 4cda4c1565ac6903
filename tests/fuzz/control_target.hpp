#pragma once

#include <algorithm>
#include <chrono>

#include "ports_target.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::fuzz {

/// The control API unit tests' target (test::PortsTarget: real servos, a hand-stepped clock)
/// for fuzz_control, with one difference: clock.step runs at most kStepCap of
/// simulated time per request, because a long step of a moving servo costs a motion tick per
/// millisecond and would make the fuzzer report slow inputs instead of bugs.
class ControlTarget : public test::PortsTarget {
 public:
  /// Simulated time one step_clock() runs at most.
  static constexpr sim::SimDuration kStepCap = std::chrono::seconds(2);

  void step_clock(sim::SimDuration d) override { scheduler.advance_by(std::min(d, kStepCap)); }
};

}  // namespace dxlemu::fuzz
