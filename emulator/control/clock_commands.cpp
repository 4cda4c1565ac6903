#include "control/clock_commands.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <string_view>
#include <utility>

#include "control/api.hpp"

namespace dxlemu::control {
namespace {

constexpr double kNsPerMs = 1e6;
constexpr double kNsPerUs = 1e3;

ordered_json time_json(sim::SimTime t) {
  const std::int64_t ns = sim::ns_since_start(t);
  return {{"ns", ns}, {"ms", static_cast<double>(ns) / kNsPerMs}};
}

}  // namespace

ordered_json clock_now(Target& target, const Args& /*args*/) {
  ordered_json result = time_json(target.now());
  result["timing"] = target.timing();
  return result;
}

ordered_json clock_step(Target& target, const Args& args) {
  if (!target.manual_clock()) {
    refuse("clock.step needs --timing manual");
  }
  struct Unit {
    std::string_view key;
    double ns;
  };
  constexpr std::array<Unit, 3> kUnits = {{{"ms", kNsPerMs}, {"us", kNsPerUs}, {"ns", 1}}};
  std::optional<std::pair<Unit, double>> step;
  for (const Unit& unit : kUnits) {
    if (const auto value = args.number(unit.key)) {
      if (step) {
        refuse("clock.step takes only one of \"ms\", \"us\" or \"ns\"");
      }
      step.emplace(unit, *value);
    }
  }
  if (!step) {
    refuse("clock.step needs one of \"ms\", \"us\" or \"ns\"");
  }
  const auto& [unit, value] = *step;
  const double ns = std::round(value * unit.ns);
  if (!(value > 0)) {
    refuse(json_quoted(unit.key) + " must be positive");
  }
  if (ns < 1) {
    refuse(json_quoted(unit.key) + " must be at least 1 ns");
  }
  if (ns > static_cast<double>(kMaxStep.count())) {
    refuse("one clock.step moves at most " +
           std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(kMaxStep).count()) +
           " ms");
  }
  target.step_clock(sim::SimDuration{static_cast<std::int64_t>(ns)});
  return time_json(target.now());
}

}  // namespace dxlemu::control
