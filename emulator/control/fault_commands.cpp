#include "control/fault_commands.hpp"

#include <algorithm>

#include "faults/rule_parser.hpp"

namespace dxlemu::control {

namespace {

std::string rule_ids(const faults::Injector& injector) {
  std::vector<std::string> ids;
  for (const auto& e : injector.rules()) {
    ids.push_back(std::to_string(e.id));
  }
  return ids.empty() ? "there are none" : "rules: " + joined(ids);
}

}  // namespace

faults::Rule rule_of(Target& target, const ordered_json* given) {
  if (given == nullptr) {
    refuse("\"rule\" is required, e.g. {\"action\":\"drop_reply\",\"match\":{\"servos\":[3]}}");
  }
  faults::Rule rule;
  try {
    rule = faults::parse_rule(nlohmann::json::parse(given->dump()));
  } catch (const faults::RuleError& e) {
    refuse("rule" + e.pointer() + ": " + e.what());
  }
  if (rule.match.port) {
    const auto names = target.port_names();
    if (std::find(names.begin(), names.end(), *rule.match.port) == names.end()) {
      refuse("rule/match/port: port " + json_quoted(*rule.match.port) +
             " does not exist (ports: " + joined(names) + ")");
    }
  }
  return rule;
}

ordered_json fault_add(Target& target, const Args& args) {
  faults::Rule rule = rule_of(target, args.value("rule"));
  const std::uint64_t id = target.faults().add(std::move(rule), target.now());
  return {{"rule", id}};
}

ordered_json fault_list(Target& target, const Args& /*args*/) {
  ordered_json out = ordered_json::array();
  const sim::SimTime now = target.now();
  for (const auto& e : target.faults().rules()) {
    const bool spent = e.rule.trigger.count && e.fired >= *e.rule.trigger.count;
    out.push_back({{"id", e.id},
                   {"rule", faults::rule_json(e.rule)},
                   {"matched", e.matched},
                   {"fired", e.fired},
                   {"active", faults::in_window(e.rule.trigger, e.added, now) && !spent}});
  }
  return out;
}

ordered_json fault_remove(Target& target, const Args& args) {
  const std::int64_t id = args.required_integer("rule");
  if (id < 1 || !target.faults().remove(static_cast<std::uint64_t>(id))) {
    refuse("no fault rule " + std::to_string(id) + " (" + rule_ids(target.faults()) + ")");
  }
  return {{"rule", id}};
}

ordered_json fault_clear(Target& target, const Args& /*args*/) {
  const std::size_t removed = target.faults().clear();
  return {{"removed", removed}};
}

}  // namespace dxlemu::control
