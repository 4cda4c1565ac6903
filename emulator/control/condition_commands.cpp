#include "control/condition_commands.hpp"

#include <optional>
#include <string_view>
#include <utility>

#include "model/servo.hpp"

namespace dxlemu::control {
namespace {

// Sane surroundings for condition.set (units: °C, V, N·m). Nothing a real servo survives lies
// outside them, and the motor model's arithmetic stays finite within them.
constexpr int kMinAmbientC = -50;
constexpr int kMaxAmbientC = 200;
constexpr int kMinSupplyV = 0;
constexpr int kMaxSupplyV = 100;
constexpr int kMaxLoadNm = 1000;

/// A number within [lo, hi], or nullopt when absent.
std::optional<double> bounded(const Args& args, std::string_view key, int lo, int hi,
                              std::string_view unit) {
  const auto value = args.number(key);
  if (value && !(*value >= lo && *value <= hi)) {
    refuse(json_quoted(key) + " must be " + std::to_string(lo) + " ~ " + std::to_string(hi) + " " +
           std::string(unit) + ", got " + args.text(key));
  }
  return value;
}

ordered_json conditions_json(const model::Conditions& c) {
  return {{"ambient_temperature", c.ambient_c},
          {"supply_voltage", c.supply_v},
          {"external_load", c.external_load_nm},
          {"blocked", c.blocked}};
}

}  // namespace

ordered_json condition_set(Target& target, const Args& args) {
  const Port port = port_of(target, args);
  const auto servo_id = args.integer("servo");
  const auto ambient = bounded(args, "ambient_temperature", kMinAmbientC, kMaxAmbientC, "°C");
  const auto supply = bounded(args, "supply_voltage", kMinSupplyV, kMaxSupplyV, "V");
  const auto load = bounded(args, "external_load", -kMaxLoadNm, kMaxLoadNm, "N·m");
  const auto blocked = args.boolean("blocked");
  if (!ambient && !supply && !load && !blocked) {
    refuse(
        "condition.set needs at least one of ambient_temperature, supply_voltage, external_load, "
        "blocked");
  }
  // Motion up to now runs under the old conditions; the new ones hold from now on.
  port.view.catch_up();
  const auto change = [&](model::Servo& servo) {
    model::Conditions c = servo.motion().conditions();
    c.ambient_c = ambient.value_or(c.ambient_c);
    c.supply_v = supply.value_or(c.supply_v);
    c.external_load_nm = load.value_or(c.external_load_nm);
    c.blocked = blocked.value_or(c.blocked);
    servo.motion().set_conditions(c);
    return conditions_json(c);
  };
  if (servo_id) {
    return change(servo_on(port, *servo_id));
  }
  ordered_json all = ordered_json::array();
  for (model::Servo* servo : port.view.servos()) {
    ordered_json entry = {{"id", servo->id()}};
    entry.update(change(*servo));
    all.push_back(std::move(entry));
  }
  return all;
}

}  // namespace dxlemu::control
