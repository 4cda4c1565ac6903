#pragma once

#include "control/request.hpp"
#include "faults/rule.hpp"

// The control API's fault commands (docs/control-api.md, docs/faults.md).
namespace dxlemu::control {

/// The rule `given` in a request, read and checked against the target's ports; refused (with
/// the member's JSON pointer under "rule") when it is missing or wrong.
faults::Rule rule_of(Target& target, const ordered_json* given);

/// fault.add {"rule": {...}}: adds a rule; the result is {"rule": id}.
ordered_json fault_add(Target& target, const Args& args);
/// fault.list: every rule with its id, counters and whether it is active now.
ordered_json fault_list(Target& target, const Args& args);
/// fault.remove {"rule": id}: removes one rule; an injected hardware error it caused is gone.
ordered_json fault_remove(Target& target, const Args& args);
/// fault.clear: removes every rule; the result is {"removed": n}.
ordered_json fault_clear(Target& target, const Args& args);

}  // namespace dxlemu::control
