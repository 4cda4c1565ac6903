#pragma once

#include "control/request.hpp"

// The control API's command on a servo's surroundings: condition.set (docs/control-api.md).
namespace dxlemu::control {

/// condition.set {"port", "servo"?, "ambient_temperature", "supply_voltage", "external_load",
/// "blocked"}: changes the conditions of one servo, or of every servo on the port; the result is
/// the conditions now (a list with "id" for a whole port).
ordered_json condition_set(Target& target, const Args& args);

}  // namespace dxlemu::control
