#pragma once

#include <cstddef>

#include "model/table/control_table.hpp"

namespace dxlemu::model {

/// Joins the two control tables of a dual-axis device (2XL430-W250): EEPROM is writable only
/// while Torque Enable of both axes is 0, and a write of a shared item (the model's
/// `shared_items`: Baud Rate, Protocol Type) on one axis changes it on the other
/// (includes/control_table_2x_warning.md; the item hook table installs that). Both tables must
/// outlive the link; call once per pair.
void link_axes(ControlTable& first, ControlTable& second);

/// A shared item was written on `from`: `to`, the other axis, holds the same value. set() runs
/// no hooks, so the copy does not echo back.
void copy_to_other_axis(const ControlTable& from, ControlTable& to, std::size_t item);

}  // namespace dxlemu::model
