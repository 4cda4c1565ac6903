#pragma once

#include "model/table/control_table.hpp"

namespace dxlemu::model {

/// Adds the write rules of the model's behaviour family that the model file cannot express as
/// ranges and limits. Today: in joint mode, Goal Position must lie between CW and CCW Angle Limit
/// (FamilyTraits::goal_within_angle_limits: includes/ax-legacy-page-description-sections.md,
/// protocol1.md "Angle Limit Error"); wheel mode (both limits 0) and multi-turn mode (both at
/// FamilyTraits::multi_turn_angle_limit) take any Goal Position in range. Bus Watchdog error (-1):
/// goal writes refused with Data Range Error until Bus Watchdog is written 0
/// (includes/control_table_buswatchdog.md). Hybrid Save (DYNAMIXEL-Y): a save request (1), taken
/// only with torque off, makes the Hybrid items' values the ones a reboot restores; the item then
/// reads 2 (Saved) until a Hybrid item changes (0). ControlTable's constructor calls this.
void install_family_rules(ControlTable& table);

}  // namespace dxlemu::model
