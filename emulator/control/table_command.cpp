#include "control/table_command.hpp"

#include <cmath>
#include <string>

#include "control/port_commands.hpp"
#include "control/unit_text.hpp"
#include "model/servo.hpp"

namespace dxlemu::control {
namespace {

// A scaled value with nothing after the point is written as an integer (2048, not 2048.0) up to
// where every integer is still a double.
constexpr double kExactIntegers = 9007199254740992.0;  // 2^53

std::string_view area_text(model::Area area) {
  switch (area) {
    case model::Area::Eeprom:
      return "EEPROM";
    case model::Area::Ram:
      return "RAM";
    case model::Area::Hybrid:
      return "Hybrid";
  }
  return "RAM";
}

ordered_json number_json(double value) {
  if (std::trunc(value) == value && std::fabs(value) < kExactIntegers) {
    return static_cast<std::int64_t>(value);
  }
  return value;
}

ordered_json item_json(const model::ItemSpec& item, std::int64_t value) {
  ordered_json out = {{"key", item.key},
                      {"name", item.name},
                      {"address", item.address},
                      {"size", item.size},
                      {"access", item.access == model::Access::ReadOnly ? "R" : "RW"},
                      {"area", area_text(item.area)},
                      {"min", item.min},
                      {"max", item.max}};
  if (!item.values.empty()) {
    out["values"] = item.values;
  }
  if (!item.unit.empty()) {
    out["unit"] = item.unit;
  }
  out["value"] = value;
  if (const auto scaled = scaled_unit(item.unit)) {
    out["scaled"] = number_json(scaled_value(value, scaled->factor));
    out["scaled_unit"] = scaled->unit;
  }
  return out;
}

}  // namespace

ordered_json servo_table(Target& target, const Args& args) {
  const Port port = port_of(target, args);
  const std::int64_t id = args.required_integer("servo");
  port.view.catch_up();
  const model::Servo& servo = servo_on(port, id);
  const model::ModelSpec& spec = servo.spec();
  ordered_json items = ordered_json::array();
  for (std::size_t i = 0; i < spec.items.size(); ++i) {
    items.push_back(item_json(spec.items[i], servo.table().get(i)));
  }
  const auto protocol = servo.protocol();
  return {{"port", port.name},
          {"servo", servo.id()},
          {"model", spec.name},
          {"protocol", protocol ? protocol_json(*protocol) : ordered_json(nullptr)},
          {"items", std::move(items)}};
}

}  // namespace dxlemu::control
