#pragma once

#include "control/request.hpp"
#include "control/samplers.hpp"

// The control API's commands that sample control-table items periodically: sample.subscribe and
// sample.unsubscribe (docs/control-api.md). They keep their state in the Api's Samplers.
namespace dxlemu::control {

/// The most items one sampler reads.
inline constexpr std::size_t kMaxSampledItems = 10;
/// The shortest and longest sampling periods, ms of simulated time.
inline constexpr double kMinSamplePeriodMs = 1;
inline constexpr double kMaxSamplePeriodMs = 1000;

/// sample.subscribe {"items": [{"port"?, "servo", "item"}, ...], "period_ms"}: from now on sends
/// the connection the items' values every period of simulated time, replacing its earlier
/// sampler. The result names each item's port, servo and item, and the period.
ordered_json sample_subscribe(Samplers& samplers, const Args& args);

/// sample.unsubscribe {}: ends the connection's sampler; the result says whether there was one.
ordered_json sample_unsubscribe(Samplers& samplers, const Args& args);

}  // namespace dxlemu::control
