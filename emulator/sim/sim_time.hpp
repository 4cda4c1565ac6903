#pragma once

#include <chrono>
#include <cstdint>

namespace dxlemu::sim {

/// The virtual clock's tag type. It deliberately has no now(): simulated time only moves when the
/// Scheduler advances it, so nothing below io/ can read a clock by accident.
struct SimClock {
  using rep = std::int64_t;
  using period = std::nano;
  using duration = std::chrono::duration<rep, period>;
  using time_point = std::chrono::time_point<SimClock>;
  static constexpr bool is_steady = true;  // NOLINT(readability-identifier-naming): chrono's name
};

/// A span of simulated time in integer nanoseconds.
using SimDuration = SimClock::duration;

/// A point in simulated time: nanoseconds since the simulation started (SimTime{} is the start).
using SimTime = SimClock::time_point;

/// Builds a SimTime from nanoseconds since the start; handy in tests and traces.
constexpr SimTime sim_time_from_ns(std::int64_t ns) {
  return SimTime{SimDuration{ns}};
}

/// Nanoseconds since the start of the simulation.
constexpr std::int64_t ns_since_start(SimTime t) {
  return t.time_since_epoch().count();
}

}  // namespace dxlemu::sim
