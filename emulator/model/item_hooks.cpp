// The item hook table: for each item key, every check and effect a bus write of it has beyond
// the model file's own rules (access, range, limits: ControlTable), whichever part of the servo
// implements it. Read the rows of a key to know what writing it does.
#include "model/item_hooks.hpp"

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/motion/motion_model.hpp"
#include "model/table/control_table.hpp"
#include "model/table/dual_axis.hpp"
#include "model/table/family_rules.hpp"

namespace dxlemu::model {
namespace {

/// A check: runs before anything of the write is committed; a refusal refuses the whole write.
using Check = TableResult (*)(const HookScope& s, std::int64_t value);
/// The range the item takes now, replacing its static range and limit items (nullopt: those).
using Range = std::optional<ItemRange> (*)(const HookScope& s);
/// A committed write of one item.
struct Written {
  std::size_t item;
  std::int64_t old_value;
  std::int64_t new_value;
  bool changed() const { return old_value != new_value; }
};
/// An effect: runs after the whole write is committed, in address order of the items.
using Effect = void (*)(const HookScope& s, const Written& w);
/// Whether the row is for this model (its family's traits, the items it has).
using Applies = bool (*)(const HookScope& s);

/// Which items a row is for.
enum class Select {
  Key,          ///< the first of `keys` the model has (DYNAMIXEL's key, then another maker's)
  HybridItems,  ///< every Hybrid item (DYNAMIXEL-Y)
  SharedItems,  ///< every item of the model's shared_items (dual-axis devices)
};

/// A rule of the servo keyed by the item that is not a hook: what a write of it does, kept here
/// so that the row says so.
enum class Rule {
  None,
  AfterStatus,  ///< the new value applies after the status (Servo::commit_deferred)
  KeepsEeprom,  ///< FEETECH Lock flag: EEPROM writes are kept over power-off only while 0
};

struct Row {
  std::array<std::string_view, 2> keys{};
  Select select = Select::Key;
  HookNeeds needs = HookNeeds::Table;
  Applies applies = nullptr;  // nullptr: every model with the item
  Check check = nullptr;
  Range range = nullptr;
  Effect effect = nullptr;
  Rule rule = Rule::None;
};

bool has(const HookScope& s, std::string_view key) {
  return s.table.spec().index_of(key).has_value();
}

const FamilyTraits& traits(const HookScope& s) {
  return s.table.spec().traits();
}

Protection& protection(const HookScope& s) {
  return s.motion->protection();
}

// The family's protections end at the next position command (ErrorEnd::PositionCommand).
bool ends_at_position_command(const HookScope& s) {
  return traits(s).error_reaction == ErrorReaction::Unload &&
         faults_ending(traits(s).error_rules, ErrorEnd::PositionCommand) != 0;
}

// The goal items a Bus Watchdog error makes read-only.
constexpr Row goal_after_watchdog(std::string_view key) {
  return {.keys = {key},
          .applies = [](const HookScope& s) { return has(s, "bus_watchdog"); },
          .check = [](const HookScope& s,
                      std::int64_t) { return goal_writable_after_bus_watchdog(s.table); }};
}

// A setting Present values are computed from (MotionItems::reading_settings lists the same):
// a client that writes Homing Offset and reads Present Position at once (LeRobot's calibration)
// sees the new offset, as on a real servo, not at the next tick.
constexpr Row reading_setting(std::string_view key, std::string_view other_maker = {}) {
  return {.keys = {key, other_maker},
          .needs = HookNeeds::Servo,
          .effect = [](const HookScope& s, const Written& w) {
            if (w.changed()) {
              s.motion->on_reading_setting();
            }
          }};
}

// Rows of one item run in the order listed: checks in turn until one refuses, effects in turn.
// A row is installed when what it needs exists (HookNeeds), so among an item's rows those that
// need only the table come first, then the servo's, then the other axis's.
// Besides these, ControlTable itself keeps EEPROM locked while Torque Enable is 1 (families with
// FamilyTraits::eeprom_locked_by_torque) or while 1.0 Lock is 1, and keeps Lock at 1 once set.
constexpr std::array kRows = {
    // --- Goal Position ---
    Row{.keys = {"goal_position"},
        .applies =
            [](const HookScope& s) {
              return traits(s).goal_within_angle_limits && has(s, "cw_angle_limit") &&
                     has(s, "ccw_angle_limit");
            },
        .check = [](const HookScope& s,
                    std::int64_t goal) { return goal_within_angle_limits(s.table, goal); }},
    goal_after_watchdog("goal_position"),
    Row{.keys = {"goal_position"},
        .needs = HookNeeds::Servo,
        .applies =
            [](const HookScope& s) {
              return has(s, "operating_mode") &&
                     traits(s).extended_goals != ExtendedGoals::ItemRange;
            },
        .range = [](const HookScope& s) { return s.motion->extended_goal_range(); }},
    // FEETECH: a position command ends the protections tripped until then, before the move
    // starts (feetech/field-behaviour.md row 7).
    Row{.keys = {"goal_position"},
        .needs = HookNeeds::Servo,
        .applies = ends_at_position_command,
        .effect = [](const HookScope& s, const Written&) { protection(s).position_commanded(); }},
    Row{.keys = {"goal_position"},
        .needs = HookNeeds::Servo,
        .effect = [](const HookScope& s,
                     const Written& w) { s.motion->on_goal_position(w.new_value); }},
    // --- the other goals ---
    goal_after_watchdog("goal_velocity"),
    // FEETECH wheel mode: Running speed is the mode's command, as Goal position is position
    // mode's (in position mode it is the speed of the moves, a setting).
    Row{.keys = {"goal_velocity", "running_speed"},
        .needs = HookNeeds::Servo,
        .applies = ends_at_position_command,
        .effect =
            [](const HookScope& s, const Written&) {
              if (s.motion->mode() == Mode::Velocity) {
                protection(s).position_commanded();
              }
            }},
    Row{.keys = {"goal_velocity", "running_speed"},
        .needs = HookNeeds::Servo,
        .applies = [](const HookScope& s) { return traits(s).torque_on_by_speed_goal; },
        .effect = [](const HookScope& s, const Written&) { s.motion->on_speed_goal(); }},
    goal_after_watchdog("goal_current"),
    goal_after_watchdog("goal_pwm"),
    // --- Torque Enable (FEETECH: Torque switch) ---
    Row{.keys = {"torque_enable", "torque_switch"},
        .needs = HookNeeds::Servo,
        .applies = [](const HookScope& s) { return has(s, "hardware_error_status"); },
        .check = [](const HookScope& s,
                    std::int64_t v) { return protection(s).refuse_torque_after_shutdown(v); }},
    Row{.keys = {"torque_enable", "torque_switch"},
        .needs = HookNeeds::Servo,
        .applies = [](const HookScope& s) { return has(s, "error_code"); },
        .check = [](const HookScope& s,
                    std::int64_t v) { return protection(s).refuse_torque_while_error_code(v); }},
    Row{.keys = {"torque_enable", "torque_switch"},
        .needs = HookNeeds::Servo,
        .effect = [](const HookScope& s,
                     const Written& w) { s.motion->on_torque_enable(w.old_value, w.new_value); }},
    Row{.keys = {"torque_enable", "torque_switch"},
        .needs = HookNeeds::Servo,
        .applies = [](const HookScope& s) { return has(s, "controller_state"); },
        .effect = [](const HookScope& s,
                     const Written&) { protection(s).publish_controller_state(); }},
    // --- Operating Mode ---
    Row{.keys = {"operating_mode"},
        .needs = HookNeeds::Servo,
        .effect =
            [](const HookScope& s, const Written& w) {
              if (w.changed()) {
                s.motion->on_operating_mode();
              }
            }},
    // --- settings the Present values are computed from ---
    reading_setting("homing_offset", "position_offset"),
    reading_setting("multi_turn_offset"),
    reading_setting("drive_mode"),
    reading_setting("moving_threshold"),
    reading_setting("cw_angle_limit"),
    reading_setting("ccw_angle_limit"),
    reading_setting("phase"),
    // --- Bus Watchdog ---
    Row{.keys = {"bus_watchdog"},
        .needs = HookNeeds::Servo,
        .applies =
            [](const HookScope& s) {
              return has(s, "error_code") && traits(s).error_codes.bus_watchdog != 0;
            },
        .effect = [](const HookScope& s,
                     const Written& w) { protection(s).bus_watchdog_written(w.new_value); }},
    // --- Torque Limit ---
    Row{.keys = {"torque_limit"},
        .needs = HookNeeds::Servo,
        .applies =
            [](const HookScope& s) {
              return traits(s).error_reaction == ErrorReaction::AlarmShutdown ||
                     (traits(s).error_reaction == ErrorReaction::Unload &&
                      faults_ending(traits(s).error_rules, ErrorEnd::TorqueLimitWritten) != 0);
            },
        .effect = [](const HookScope& s, const Written&) { protection(s).torque_limit_written(); }},
    // --- Hybrid Save and the Hybrid items (DYNAMIXEL-Y) ---
    Row{.keys = {"hybrid_save"},
        .check = [](const HookScope& s, std::int64_t v) { return hybrid_save_allowed(s.table, v); },
        .effect = [](const HookScope& s,
                     const Written& w) { hybrid_save_written(s.table, w.new_value); }},
    Row{.select = Select::HybridItems,
        .applies = [](const HookScope& s) { return has(s, "hybrid_save"); },
        .effect = [](const HookScope& s, const Written&) { show_hybrid_state(s.table); }},
    // --- identity: applies after the status of the instruction that wrote it ---
    Row{.keys = {"id"}, .rule = Rule::AfterStatus},
    Row{.keys = {"baud_rate"}, .rule = Rule::AfterStatus},
    Row{.keys = {"return_delay_time"}, .rule = Rule::AfterStatus},
    // MX-64(2.0) and MX-106(2.0) name address 13 "Protocol Version".
    Row{.keys = {"protocol_type", "protocol_version"}, .rule = Rule::AfterStatus},
    // --- items both axes of a dual-axis device share (Baud Rate, Protocol Type) ---
    Row{.select = Select::SharedItems,
        .needs = HookNeeds::OtherAxis,
        .effect = [](const HookScope& s,
                     const Written& w) { copy_to_other_axis(s.table, *s.other_axis, w.item); }},
    // --- FEETECH Lock flag ---
    Row{.keys = {"lock_flag"},
        .needs = HookNeeds::Servo,
        .applies = [](const HookScope& s) { return traits(s).lock_flag_keeps_eeprom; },
        .rule = Rule::KeepsEeprom},
};

/// The first of the row's keys the model has.
std::optional<std::size_t> keyed_item(const ModelSpec& spec, const Row& row) {
  for (const std::string_view key : row.keys) {
    if (!key.empty()) {
      if (const auto i = spec.index_of(key)) {
        return i;
      }
    }
  }
  return std::nullopt;
}

std::vector<std::size_t> items_of(const ModelSpec& spec, const Row& row) {
  std::vector<std::size_t> out;
  switch (row.select) {
    case Select::Key:
      if (const auto i = keyed_item(spec, row)) {
        out.push_back(*i);
      }
      break;
    case Select::HybridItems:
      for (std::size_t i = 0; i < spec.items.size(); ++i) {
        if (spec.items[i].area == Area::Hybrid) {
          out.push_back(i);
        }
      }
      break;
    case Select::SharedItems:
      for (const std::string& key : spec.shared_items) {
        out.push_back(*spec.index_of(key));
      }
      break;
  }
  return out;
}

void install(const HookScope& scope, const Row& row, std::size_t item) {
  ControlTable& table = scope.table;
  const std::string& key = table.spec().items[item].key;
  if (row.check != nullptr) {
    table.add_validator(key, [scope, check = row.check](std::size_t, std::int64_t value) {
      return check(scope, value);
    });
  }
  if (row.range != nullptr) {
    table.set_range_rule(key, [scope, range = row.range](std::size_t) { return range(scope); });
  }
  if (row.effect != nullptr) {
    table.on_write(key, [scope, effect = row.effect](std::size_t i, std::int64_t old_value,
                                                     std::int64_t new_value) {
      effect(scope, Written{i, old_value, new_value});
    });
  }
  if (row.rule == Rule::KeepsEeprom) {
    // "write 0 ... values written to EEPROM addresses persist after power-off; write 1 ... do
    // not persist". What the table holds now counts as set at the factory.
    table.set_eeprom_keep([&table, item] { return table.get(item) == 0; });
  }
}

}  // namespace

void install_item_hooks(const HookScope& scope, HookNeeds needs) {
  const ModelSpec& spec = scope.table.spec();
  for (const Row& row : kRows) {
    if (row.needs != needs || (row.applies != nullptr && !row.applies(scope))) {
      continue;
    }
    for (const std::size_t item : items_of(spec, row)) {
      install(scope, row, item);
    }
  }
}

bool applies_after_status(const ModelSpec& spec, std::size_t item) {
  for (const Row& row : kRows) {
    if (row.rule == Rule::AfterStatus && keyed_item(spec, row) == item) {
      return true;
    }
  }
  return false;
}

}  // namespace dxlemu::model
