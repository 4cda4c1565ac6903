#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "faults/rule.hpp"

namespace dxlemu::faults {

/// A rule that cannot be used: `pointer` is the JSON pointer of the offending member inside the
/// rule object ("/match/servos/0", or "" for the rule itself) and `reason` says what is wrong.
class RuleError : public std::runtime_error {
 public:
  RuleError(std::string pointer, const std::string& reason)
      : std::runtime_error(reason), pointer_(std::move(pointer)) {}
  /// The JSON pointer of the offending member, relative to the rule object.
  const std::string& pointer() const { return pointer_; }

 private:
  std::string pointer_;
};

/// Reads a rule in the format of docs/faults.md. Strict: unknown members, wrong types, values out
/// of range, and parameters or triggers the action does not take are refused with RuleError.
Rule parse_rule(const nlohmann::json& rule);

/// The rule as JSON in the format parse_rule reads, with every default spelled out (for
/// fault.list).
nlohmann::ordered_json rule_json(const Rule& rule);

}  // namespace dxlemu::faults
