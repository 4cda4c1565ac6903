#pragma once

#include <cstddef>
#include <string>

#include "control/request.hpp"

// The control API's commands on one servo's control table: get and set (docs/control-api.md).
namespace dxlemu::control {

/// The index of the item `key` of `spec`; refused naming the model when it has none.
std::size_t item_named(const model::ModelSpec& spec, const std::string& key);

/// get {"port", "servo", "item"} or {..., "address", "size"}: an item's value, or raw bytes of
/// the image read device-side (no access rules, read hooks or Indirect Data mapping).
ordered_json get(Target& target, const Args& args);
/// set {"port", "servo", "item" or "address" and "size", "value"}: writes an item device-side
/// (model::Servo::device_write); the result is the item's value afterwards.
ordered_json set(Target& target, const Args& args);

}  // namespace dxlemu::control
