#include "model/spec/model_spec.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <stdexcept>

namespace dxlemu::model {

std::optional<double> unit_figure(std::string_view unit) {
  constexpr std::string_view kAbout = "about";
  while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit.front())) != 0) {
    unit.remove_prefix(1);
  }
  if (unit.starts_with(kAbout)) {
    unit.remove_prefix(kAbout.size());
    while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit.front())) != 0) {
      unit.remove_prefix(1);
    }
  }
  double figure = 0;
  const auto [end, error] = std::from_chars(unit.data(), unit.data() + unit.size(), figure);
  if (error != std::errc{} || end == unit.data() || figure <= 0) {
    return std::nullopt;
  }
  return figure;
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
