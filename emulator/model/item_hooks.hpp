#pragma once

#include <cstddef>

namespace dxlemu::model {

class ControlTable;
class MotionModel;
struct ModelSpec;

/// What the item hooks of one control table work on: the table, and the parts of the device it
/// belongs to once there is one. Whoever installs hooks with it keeps them alive as long as the
/// table (Servo, link_axes).
struct HookScope {
  ControlTable& table;
  MotionModel* motion = nullptr;       ///< the servo's motion model, for HookNeeds::Servo rows
  ControlTable* other_axis = nullptr;  ///< the other axis's table, for HookNeeds::OtherAxis rows
};

/// What a row of the item hook table needs besides the table, which says when it is installed.
enum class HookNeeds {
  Table,     ///< nothing more: the table's constructor installs it (the family's rules)
  Servo,     ///< the servo's motion model: Servo's constructor installs it
  OtherAxis  ///< the other axis of a dual-axis device: link_axes() installs it
};

/// Installs on `scope.table` every row of the item hook table (item_hooks.cpp) that needs
/// `needs` and applies to the table's model; `scope` must hold what `needs` names.
void install_item_hooks(const HookScope& scope, HookNeeds needs);

/// True when a bus write of item `item` of `spec` takes effect only after the status of the
/// instruction that wrote it (ID, Baud Rate, Return Delay Time, Protocol Type): Servo applies it
/// at commit_deferred().
bool applies_after_status(const ModelSpec& spec, std::size_t item);

}  // namespace dxlemu::model
