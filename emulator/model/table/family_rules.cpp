#include "model/table/family_rules.hpp"

#include <optional>
#include <string>

namespace dxlemu::model {
namespace {

void install_angle_limit(ControlTable& table) {
  const ModelSpec& spec = table.spec();
  const auto cw = spec.index_of("cw_angle_limit");
  const auto ccw = spec.index_of("ccw_angle_limit");
  if (!cw || !ccw || !spec.find("goal_position")) {
    return;
  }
  const std::optional<std::int64_t> multi_turn = spec.traits().multi_turn_angle_limit;
  table.add_validator(
      "goal_position", [&table, cw = *cw, ccw = *ccw, multi_turn](std::size_t, std::int64_t goal) {
        const std::int64_t lo = table.get(cw);
        const std::int64_t hi = table.get(ccw);
        const bool wheel = lo == 0 && hi == 0;
        const bool turns = multi_turn && lo == *multi_turn && hi == *multi_turn;
        if (wheel || turns || (goal >= lo && goal <= hi)) {
          return TableResult{};
        }
        return TableResult::fail(TableError::AngleLimit, "goal_position " + std::to_string(goal) +
                                                             " is outside CW/CCW Angle Limit (" +
                                                             std::to_string(lo) + " ~ " +
                                                             std::to_string(hi) + ")");
      });
}

// includes/control_table_buswatchdog.md: after a Bus Watchdog error (-1) "the Goal Value ... will
// be changed to read-only-access ... the Status Packet will send the Data Range Error" until
// Bus Watchdog is written 0.
void install_bus_watchdog(ControlTable& table) {
  const auto watchdog = table.spec().index_of("bus_watchdog");
  if (!watchdog) {
    return;
  }
  for (const std::string_view goal :
       {"goal_pwm", "goal_current", "goal_velocity", "goal_position"}) {
    if (table.spec().index_of(goal)) {
      table.add_validator(goal, [&table, watchdog = *watchdog](std::size_t, std::int64_t) {
        if (table.get(watchdog) >= 0) {
          return TableResult{};
        }
        return TableResult::fail(TableError::DataRange,
                                 "Bus Watchdog error: goal values are read-only until Bus "
                                 "Watchdog is written 0");
      });
    }
  }
}

// Hybrid Save(170) values (_includes/en/dxl/y/control_table_170_hybrid_save.md of
// ROBOTIS-GIT/emanual): 0 Changed (unsaved Hybrid values), 1 Save Request, 2 Saved.
constexpr std::int64_t kHybridChanged = 0;
constexpr std::int64_t kHybridSaveRequest = 1;
constexpr std::int64_t kHybridSaved = 2;

// DYNAMIXEL-Y: Hybrid items are written like RAM and survive a reboot once saved: writing 1 to
// Hybrid Save stores them ("'1' can be used when the Torque Enable(512) value is '0'"), and
// Hybrid Save then reads 2 until a Hybrid item changes again (0).
void install_hybrid_save(ControlTable& table) {
  const ModelSpec& spec = table.spec();
  const auto save = spec.index_of("hybrid_save");
  if (!save) {
    return;
  }
  const auto torque = spec.index_of("torque_enable");
  table.add_validator("hybrid_save", [&table, torque](std::size_t, std::int64_t v) {
    if (v == kHybridSaveRequest && torque && table.get(*torque) != 0) {
      return TableResult::fail(TableError::ResultFail,
                               "Hybrid Save takes a save request only while Torque Enable is 0");
    }
    return TableResult{};
  });
  const auto show_state = [&table, save = *save] {
    table.set(save, table.hybrid_changed() ? kHybridChanged : kHybridSaved);
  };
  table.on_write("hybrid_save", [&table, show_state](std::size_t, std::int64_t, std::int64_t v) {
    if (v == kHybridSaveRequest) {
      table.save_hybrid();
    }
    show_state();
  });
  for (const ItemSpec& item : spec.items) {
    if (item.area == Area::Hybrid) {
      table.on_write(item.key,
                     [show_state](std::size_t, std::int64_t, std::int64_t) { show_state(); });
    }
  }
}

}  // namespace

void install_family_rules(ControlTable& table) {
  if (table.spec().traits().goal_within_angle_limits) {
    install_angle_limit(table);
  }
  install_bus_watchdog(table);
  install_hybrid_save(table);
}

}  // namespace dxlemu::model
