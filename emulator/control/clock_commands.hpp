#pragma once

#include "control/request.hpp"

// The control API's commands on simulated time: clock.now and clock.step (docs/control-api.md,
// docs/timing.md).
namespace dxlemu::control {

/// clock.now: simulated time as {"ns", "ms"}.
ordered_json clock_now(Target& target, const Args& args);
/// clock.step {"ms" | "us" | "ns"}: moves simulated time forward (--timing manual only, at most
/// kMaxStep); the result is the time afterwards.
ordered_json clock_step(Target& target, const Args& args);

}  // namespace dxlemu::control
