#pragma once

#include "control/request.hpp"

// The control API's view of a whole control table: table (docs/control-api.md).
namespace dxlemu::control {

/// table {"port", "servo"}: every item of the servo's control table with what its model file says
/// of it (address, size, access, area, range, unit) and its value as get reads it, scaled by its
/// unit when the unit is "NUMBER [UNIT]".
ordered_json servo_table(Target& target, const Args& args);

}  // namespace dxlemu::control
