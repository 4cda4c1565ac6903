#include "model/table/family_rules.hpp"

#include <optional>
#include <string>

namespace dxlemu::model {
namespace {

// Hybrid Save(170) values (_includes/en/dxl/y/control_table_170_hybrid_save.md of
// ROBOTIS-GIT/emanual): 0 Changed (unsaved Hybrid values), 1 Save Request, 2 Saved.
constexpr std::int64_t kHybridChanged = 0;
constexpr std::int64_t kHybridSaveRequest = 1;
constexpr std::int64_t kHybridSaved = 2;

}  // namespace

TableResult goal_within_angle_limits(const ControlTable& table, std::int64_t goal) {
  const std::int64_t lo = table.get(table.index("cw_angle_limit"));
  const std::int64_t hi = table.get(table.index("ccw_angle_limit"));
  const std::optional<std::int64_t> multi_turn = table.spec().traits().multi_turn_angle_limit;
  const bool wheel = lo == 0 && hi == 0;
  const bool turns = multi_turn && lo == *multi_turn && hi == *multi_turn;
  if (wheel || turns || (goal >= lo && goal <= hi)) {
    return {};
  }
  return TableResult::fail(TableError::AngleLimit, "goal_position " + std::to_string(goal) +
                                                       " is outside CW/CCW Angle Limit (" +
                                                       std::to_string(lo) + " ~ " +
                                                       std::to_string(hi) + ")");
}

// includes/control_table_buswatchdog.md: after a Bus Watchdog error (-1) "the Goal Value ... will
// be changed to read-only-access ... the Status Packet will send the Data Range Error" until
// Bus Watchdog is written 0.
TableResult goal_writable_after_bus_watchdog(const ControlTable& table) {
  if (table.get(table.index("bus_watchdog")) >= 0) {
    return {};
  }
  return TableResult::fail(TableError::DataRange,
                           "Bus Watchdog error: goal values are read-only until Bus Watchdog is "
                           "written 0");
}

// DYNAMIXEL-Y: Hybrid items are written like RAM and survive a reboot once saved: writing 1 to
// Hybrid Save stores them ("'1' can be used when the Torque Enable(512) value is '0'"), and
// Hybrid Save then reads 2 until a Hybrid item changes again (0).
TableResult hybrid_save_allowed(const ControlTable& table, std::int64_t value) {
  const auto torque = table.spec().index_of("torque_enable");
  if (value == kHybridSaveRequest && torque && table.get(*torque) != 0) {
    return TableResult::fail(TableError::ResultFail,
                             "Hybrid Save takes a save request only while Torque Enable is 0");
  }
  return {};
}

void hybrid_save_written(ControlTable& table, std::int64_t value) {
  if (value == kHybridSaveRequest) {
    table.save_hybrid();
  }
  show_hybrid_state(table);
}

void show_hybrid_state(ControlTable& table) {
  table.set(table.index("hybrid_save"), table.hybrid_changed() ? kHybridChanged : kHybridSaved);
}

}  // namespace dxlemu::model
