#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "control/request.hpp"
#include "control/target.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::control {

/// A scenario that cannot be used: `pointer` is the JSON pointer of the offending member
/// ("/steps/2/at_ms") and what() the reason.
class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string pointer, const std::string& reason)
      : std::runtime_error(reason), pointer_(std::move(pointer)) {}
  /// The JSON pointer of the offending member.
  const std::string& pointer() const { return pointer_; }

 private:
  std::string pointer_;
};

/// One step of a scenario: a control request to run `at` after the scenario was loaded.
struct ScenarioStep {
  sim::SimDuration at{0};
  nlohmann::ordered_json request;  ///< {"cmd": ..., arguments}, without "at_ms"
  std::string pointer;             ///< where the step is in the scenario ("/steps/3")
};

/// The most steps one scenario may have.
inline constexpr std::size_t kMaxScenarioSteps = 10000;

/// Reads a scenario, {"steps": [{"at_ms": 0, "cmd": "fault.add", "rule": {...}}, ...]}
/// (docs/faults.md "Scenarios"). Only the shape is checked here; the caller checks each request.
/// Throws ScenarioError.
std::vector<ScenarioStep> parse_scenario(const nlohmann::ordered_json& scenario);

/// The commands a scenario step may run: those that change the bus (faults, conditions, items,
/// plugging, shutdown), not those that read or need a connection.
bool allowed_in_scenario(std::string_view command);

/// A scenario scheduled: its number in Target::scenarios() and how many steps it has.
struct ScheduledScenario {
  std::size_t number = 0;
  std::size_t steps = 0;
};

/// Checks every step of `scenario` against `target` (commands, arguments, rules, ports, servos)
/// and then schedules each to run at its time after now, recording the scenario in
/// Target::scenarios() under `origin` (its file's path, or "request"); each step reports there
/// when it runs. A step that fails when it runs is also reported with Target::warn naming
/// `origin` and the step. Throws ScenarioError (and schedules and records nothing) for a bad
/// scenario.
ScheduledScenario schedule_scenario(Target& target, const nlohmann::ordered_json& scenario,
                                    const std::string& origin);

/// Reads the JSON of scenario file `path`. Throws ScenarioError when it cannot be read or parsed.
nlohmann::ordered_json load_scenario_file(const std::filesystem::path& path);

/// scenario.load {"file": PATH} or {"scenario": {...}}: schedules the scenario's steps; the
/// result is {"steps": n, "scenario": its number}.
ordered_json scenario_load(Target& target, const Args& args);

/// scenario.list: every scenario loaded so far with its progress (Target::scenarios()).
ordered_json scenario_list(Target& target, const Args& args);

}  // namespace dxlemu::control
