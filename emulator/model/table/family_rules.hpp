#pragma once

#include <cstddef>
#include <cstdint>

#include "model/table/control_table.hpp"

// The write rules of the behaviour families that a model file cannot express as ranges and
// limits. They need nothing but the table; the item hook table (model/item_hooks.cpp) says which
// item's write runs which of them, for which models.

namespace dxlemu::model {

/// In joint mode, Goal Position must lie between CW and CCW Angle Limit (Angle Limit Error);
/// wheel mode (both limits 0) and multi-turn mode (both at FamilyTraits::multi_turn_angle_limit)
/// take any Goal Position in range (FamilyTraits::goal_within_angle_limits:
/// includes/ax-legacy-page-description-sections.md, protocol1.md "Angle Limit Error"). The model
/// must have both angle limit items.
TableResult goal_within_angle_limits(const ControlTable& table, std::int64_t goal);

/// After a Bus Watchdog error (Bus Watchdog -1) goal values are refused with Data Range Error
/// until Bus Watchdog is written 0 (includes/control_table_buswatchdog.md). The model must have
/// Bus Watchdog.
TableResult goal_writable_after_bus_watchdog(const ControlTable& table);

/// DYNAMIXEL-Y Hybrid Save: a save request (1) is taken only with torque off.
TableResult hybrid_save_allowed(const ControlTable& table, std::int64_t value);

/// DYNAMIXEL-Y Hybrid Save written `value`: a save request makes the Hybrid items' values the
/// ones a reboot restores; the item then reads 2 (Saved) until a Hybrid item changes (0).
void hybrid_save_written(ControlTable& table, std::int64_t value);

/// A Hybrid item was written: Hybrid Save shows whether the Hybrid items are saved (2) or not (0).
void show_hybrid_state(ControlTable& table);

}  // namespace dxlemu::model
