#include "control/scenario.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "control/api.hpp"

namespace dxlemu::control {

namespace {

constexpr double kNsPerMs = 1e6;
// A day of simulated time: later steps are surely a unit mistake.
constexpr double kMaxAtMs = 86'400'000;

// What a step may do: change the bus, its servos and their world; never read or wait.
constexpr std::array<std::string_view, 14> kAllowed = {
    "set",        "condition.set", "servo.detach", "servo.attach",  "servo.power_cycle",
    "fault.add",  "fault.remove",  "fault.clear",  "physics.apply", "hand.play",
    "hand.sweep", "hand.move",     "hand.stop",    "shutdown"};

std::string allowed_list() {
  std::string out;
  for (const auto allowed : kAllowed) {
    out += (out.empty() ? "" : ", ") + std::string(allowed);
  }
  return out;
}

}  // namespace

bool allowed_in_scenario(std::string_view command) {
  return std::find(kAllowed.begin(), kAllowed.end(), command) != kAllowed.end();
}

std::vector<ScenarioStep> parse_scenario(const nlohmann::ordered_json& scenario) {
  if (!scenario.is_object()) {
    throw ScenarioError("", "a scenario must be a JSON object with \"steps\"");
  }
  for (const auto& [key, value] : scenario.items()) {
    if (key != "steps" && key != "description") {
      throw ScenarioError("/" + key, "unknown member (a scenario has steps and description)");
    }
  }
  const auto steps = scenario.find("steps");
  if (steps == scenario.end() || !steps->is_array()) {
    throw ScenarioError("/steps", "must be an array of steps");
  }
  if (steps->size() > kMaxScenarioSteps) {
    throw ScenarioError("/steps", "more than " + std::to_string(kMaxScenarioSteps) + " steps");
  }
  std::vector<ScenarioStep> out;
  for (std::size_t i = 0; i < steps->size(); ++i) {
    const std::string pointer = "/steps/" + std::to_string(i);
    const auto& step = (*steps)[i];
    if (!step.is_object()) {
      throw ScenarioError(pointer, "a step must be an object with at_ms and cmd");
    }
    const auto at = step.find("at_ms");
    if (at == step.end() || !at->is_number() || !std::isfinite(at->get<double>()) ||
        at->get<double>() < 0 || at->get<double>() > kMaxAtMs) {
      throw ScenarioError(pointer + "/at_ms",
                          "must be the step's time in ms after loading, from 0 to 86400000");
    }
    const auto cmd = step.find("cmd");
    if (cmd == step.end() || !cmd->is_string()) {
      throw ScenarioError(pointer + "/cmd", "must be a command name");
    }
    if (!allowed_in_scenario(cmd->get<std::string>())) {
      throw ScenarioError(pointer + "/cmd",
                          cmd->dump() + " cannot be a step (steps may use " + allowed_list() + ")");
    }
    nlohmann::ordered_json request = step;
    request.erase("at_ms");
    out.push_back(
        {sim::SimDuration(static_cast<std::int64_t>(std::llround(at->get<double>() * kNsPerMs))),
         std::move(request), pointer});
  }
  return out;
}

ScheduledScenario schedule_scenario(Target& target, const nlohmann::ordered_json& scenario,
                                    const std::string& origin) {
  std::vector<ScenarioStep> steps = parse_scenario(scenario);
  // Every step is checked before any is scheduled: a scenario runs whole or not at all.
  for (const ScenarioStep& step : steps) {
    if (const auto problem = Api::check(target, step.request)) {
      throw ScenarioError(step.pointer, *problem);
    }
  }
  std::vector<sim::SimDuration> times;
  times.reserve(steps.size());
  for (const ScenarioStep& step : steps) {
    times.push_back(step.at);
  }
  const std::size_t number = target.scenarios().add(origin, target.now(), std::move(times));
  for (ScenarioStep& step : steps) {
    target.schedule_in(step.at, [&target, number, request = std::move(step.request),
                                 where = origin + " " + step.pointer] {
      const nlohmann::ordered_json reply = Api(target).run(request);
      const bool ok = reply.value("ok", false);
      target.scenarios().step_ran(number, ok);
      if (!ok) {
        target.warn("scenario " + where + ": " + reply.value("error", std::string("failed")));
      }
    });
  }
  return {number, steps.size()};
}

nlohmann::ordered_json load_scenario_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw ScenarioError("", "cannot be read");
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::ordered_json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    throw ScenarioError("", std::string("not valid JSON: ") + e.what());
  }
}

ordered_json scenario_load(Target& target, const Args& args) {
  const bool file = args.has("file");
  if (file == args.has("scenario")) {
    refuse("give either \"file\" (a scenario file's path) or \"scenario\" (the scenario itself)");
  }
  const std::string origin = file ? *args.string("file") : "request";
  try {
    // A running daemon must not read a FIFO (its only thread would block until someone writes to
    // it: bus and control API stopped) or a device such as /dev/zero (read without end). At
    // start, --scenario <(...) may be a pipe: that stays allowed.
    if (file) {
      std::error_code ec;
      const auto status = std::filesystem::status(origin, ec);
      if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
        throw ScenarioError("", "is not a regular file");
      }
    }
    const ScheduledScenario scheduled = schedule_scenario(
        target, file ? load_scenario_file(origin) : *args.value("scenario"), origin);
    return {{"steps", scheduled.steps}, {"scenario", scheduled.number}};
  } catch (const ScenarioError& e) {
    refuse((file ? origin + ": " : std::string("scenario")) + e.pointer() +
           (file && e.pointer().empty() ? "" : ": ") + e.what());
  }
}

ordered_json scenario_list(Target& target, const Args& /*args*/) {
  const auto ms = [](sim::SimTime t) {
    return static_cast<double>(sim::ns_since_start(t)) / kNsPerMs;
  };
  ordered_json out = ordered_json::array();
  for (const ScenarioRegistry::Progress& p : target.scenarios().all()) {
    const auto next = p.next_at();
    out.push_back({{"scenario", p.number},
                   {"origin", p.origin},
                   {"steps", p.times.size()},
                   {"done", p.done},
                   {"failed", p.failed},
                   {"next_at_ms", next ? ordered_json(ms(*next)) : ordered_json(nullptr)},
                   {"loaded_at_ms", ms(p.loaded_at)}});
  }
  return out;
}

}  // namespace dxlemu::control
