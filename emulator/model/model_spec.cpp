#include "model/model_spec.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

namespace dxlemu::model {
namespace {

constexpr std::array<std::pair<Family, std::string_view>, 9> kFamilyNames = {{
    {Family::X, "x"},
    {Family::Mx2, "mx2"},
    {Family::Mx1, "mx1"},
    {Family::Ax, "ax"},
    {Family::Rx, "rx"},
    {Family::Ex, "ex"},
    {Family::Xl320, "xl320"},
    {Family::P, "p"},
    {Family::Pro, "pro"},
}};

}  // namespace

std::string_view family_name(Family family) {
  for (const auto& [f, name] : kFamilyNames) {
    if (f == family) {
      return name;
    }
  }
  return "?";
}

std::optional<Family> family_from_name(std::string_view name) {
  for (const auto& [f, n] : kFamilyNames) {
    if (n == name) {
      return f;
    }
  }
  return std::nullopt;
}

bool locks_eeprom_with_torque(Family family) {
  switch (family) {
    case Family::X:
    case Family::Mx2:
    case Family::Xl320:
    case Family::P:
    case Family::Pro:
      return true;
    case Family::Mx1:
    case Family::Ax:
    case Family::Rx:
    case Family::Ex:
      return false;
  }
  return false;
}

bool ItemSpec::in_range(std::int64_t value) const {
  if (value < min || value > max) {
    return false;
  }
  return values.empty() || std::find(values.begin(), values.end(), value) != values.end();
}

const ItemSpec* ModelSpec::find(std::string_view key) const {
  const auto index = index_of(key);
  return index ? &items[*index] : nullptr;
}

void ModelSpec::index_items() {
  item_index.clear();
  for (std::size_t i = 0; i < items.size(); ++i) {
    item_index.emplace(items[i].key, i);
  }
}

std::optional<std::size_t> ModelSpec::index_of(std::string_view key) const {
  if (item_index.size() != items.size()) {
    throw std::logic_error("model " + name + ": items are not indexed (ModelSpec::index_items)");
  }
  const auto found = item_index.find(key);
  if (found == item_index.end()) {
    return std::nullopt;
  }
  return found->second;
}

std::size_t ModelSpec::table_size() const {
  std::size_t end = 0;
  for (const ItemSpec& item : items) {
    end = std::max(end, item.end());
  }
  return end;
}

std::optional<std::uint32_t> ModelSpec::bps_for_index(std::int64_t index) const {
  for (const BaudRate& b : baud_rates) {
    if (b.index == index) {
      return b.bps;
    }
  }
  return std::nullopt;
}

}  // namespace dxlemu::model
