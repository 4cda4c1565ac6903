#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sim/sim_time.hpp"

namespace dxlemu::control {

/// The scenarios loaded so far (scenario.load, --scenario) and how far each has run: what
/// scenario.list shows. Target::scenarios() keeps it; each scheduled step reports to it when it
/// runs. Simulated time only: no clock of its own.
class ScenarioRegistry {
 public:
  /// One loaded scenario.
  struct Progress {
    std::size_t number = 0;               ///< 1 for the first scenario loaded, then 2, ...
    std::string origin;                   ///< its file's path, or "request"
    sim::SimTime loaded_at;               ///< when it was loaded: its steps' times count from here
    std::vector<sim::SimDuration> times;  ///< every step's time after loaded_at, earliest first
    std::size_t done = 0;                 ///< steps that have run, refused ones included
    std::size_t failed = 0;               ///< steps that ran and were refused
    /// When the next step runs (the steps run in time order), or nullopt when all have.
    std::optional<sim::SimTime> next_at() const {
      return done < times.size() ? std::optional(loaded_at + times[done]) : std::nullopt;
    }
  };

  /// Records a scenario from `origin` loaded at `now` whose steps run at `times` after it (in
  /// any order); returns its number.
  std::size_t add(std::string origin, sim::SimTime now, std::vector<sim::SimDuration> times);

  /// A step of scenario `number` has run; `ok` is false when it was refused. An unknown number
  /// is ignored.
  void step_ran(std::size_t number, bool ok);

  /// Every scenario loaded, in the order they were.
  const std::vector<Progress>& all() const { return scenarios_; }

 private:
  std::vector<Progress> scenarios_;
};

}  // namespace dxlemu::control
