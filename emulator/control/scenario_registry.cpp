#include "control/scenario_registry.hpp"

#include <algorithm>
#include <utility>

namespace dxlemu::control {

std::size_t ScenarioRegistry::add(std::string origin, sim::SimTime now,
                                  std::vector<sim::SimDuration> times) {
  std::sort(times.begin(), times.end());
  Progress& added = scenarios_.emplace_back();
  added.number = scenarios_.size();
  added.origin = std::move(origin);
  added.loaded_at = now;
  added.times = std::move(times);
  return added.number;
}

void ScenarioRegistry::step_ran(std::size_t number, bool ok) {
  if (number == 0 || number > scenarios_.size()) {
    return;
  }
  Progress& progress = scenarios_[number - 1];
  ++progress.done;
  if (!ok) {
    ++progress.failed;
  }
}

}  // namespace dxlemu::control
