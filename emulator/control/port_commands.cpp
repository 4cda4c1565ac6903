#include "control/port_commands.hpp"

#include <array>
#include <cstdio>
#include <optional>
#include <string_view>
#include <utility>

#include "model/servo.hpp"

namespace dxlemu::control {
namespace {

/// The key state of a servo that `list` shows, each only when the model has the item: the first
/// of `items` it has (DYNAMIXEL's key, then FEETECH's where it differs).
struct SummaryItem {
  std::string_view field;
  std::array<std::string_view, 2> items;
  bool boolean;
};
constexpr std::array<SummaryItem, 8> kSummaryItems = {{
    {"firmware_version", {"firmware_version", "firmware_major_version"}, false},
    {"torque", {"torque_enable", "torque_switch"}, true},
    {"present_position", {"present_position"}, false},
    {"present_temperature", {"present_temperature"}, false},
    {"present_input_voltage", {"present_input_voltage", "present_voltage"}, false},
    {"hardware_error_status", {"hardware_error_status"}, false},
    {"servo_status", {"servo_status"}, false},
    {"moving", {"moving", "moving_flag"}, true},
}};

ordered_json servo_summary(const model::Servo& servo) {
  const auto protocol = servo.protocol();
  ordered_json out = {
      {"id", servo.id()},
      {"model", servo.spec().name},
      {"protocol", protocol ? protocol_json(*protocol) : ordered_json(nullptr)},
      {"baud", servo.baud_bps()},
  };
  for (const SummaryItem& summary : kSummaryItems) {
    for (const std::string_view key : summary.items) {
      const auto index = key.empty() ? std::nullopt : servo.spec().index_of(key);
      if (!index) {
        continue;
      }
      const std::int64_t value = servo.table().get(*index);
      if (summary.boolean) {
        out[std::string(summary.field)] = value != 0;
      } else {
        out[std::string(summary.field)] = value;
      }
      break;
    }
  }
  return out;
}

double microseconds(sim::SimDuration d) {
  return static_cast<double>(d.count()) / 1e3;
}

ordered_json lateness_json(const bus::LatenessSummary& s) {
  ordered_json over = ordered_json::object();
  for (std::size_t i = 0; i < s.over.size(); ++i) {
    over[std::to_string(bus::LatenessSummary::kThresholds[i].count()) + "ms"] = s.over[i];
  }
  return {{"deliveries", s.deliveries},
          {"p50_us", microseconds(s.p50)},
          {"p99_us", microseconds(s.p99)},
          {"max_us", microseconds(s.max)},
          {"over", std::move(over)},
          {"dropped", s.dropped},
          {"drop_after_ms", static_cast<double>(s.drop_after.count()) / 1e6}};
}

/// Servo ID → item key → how many times a bus instruction wrote that EEPROM item, for the items
/// written at least once. Servos sharing an ID share an entry: their counts add up.
ordered_json eeprom_writes_json(const PortView& view) {
  ordered_json out = ordered_json::object();
  for (const model::Servo* servo : view.servos()) {
    const model::ModelSpec& spec = servo->spec();
    for (std::size_t i = 0; i < spec.items.size(); ++i) {
      if (const std::uint64_t writes = servo->eeprom_writes(i); writes != 0) {
        ordered_json& count = out[std::to_string(servo->id())][spec.items[i].key];
        count = (count.is_null() ? 0 : count.get<std::uint64_t>()) + writes;
      }
    }
  }
  return out;
}

ordered_json stats_json(const PortView& view) {
  const bus::BusStats s = view.stats();
  ordered_json out = {
      {"bytes_in", s.bytes_in},           {"frames", s.frames},
      {"garbage_bytes", s.garbage_bytes}, {"bad_checks", s.bad_checks},
      {"truncated", s.truncated},         {"impossible_lengths", s.impossible_lengths},
      {"decode_errors", s.decode_errors}, {"replies", s.replies},
      {"unread_drops", s.unread_drops},   {"collisions", s.collisions},
      {"id_conflicts", s.id_conflicts},   {"faults_injected", s.faults_injected}};
  if (const auto lateness = view.lateness()) {
    out["lateness"] = lateness_json(*lateness);
  }
  out["eeprom_writes"] = eeprom_writes_json(view);
  return out;
}

/// The port and servo a request addresses, for commands that act on the bus side of a servo.
struct Plugged {
  Port port;
  model::Servo& servo;
};

Plugged plugged(Target& target, const Args& args) {
  Port port = port_of(target, args);
  const std::int64_t id = args.required_integer("servo");
  port.view.catch_up();
  return {port, servo_on(port, id)};
}

/// Runs `instruction` on a plugged-in servo that is not booting, as if the bus addressed it;
/// refused, naming the error, when the servo would answer it with an error status.
ordered_json instruct(const Plugged& p, wire::Instruction instruction, std::string_view what) {
  const std::string servo = "servo " + std::to_string(p.servo.id()) + " on " + p.port.name;
  if (!p.port.view.attached(p.servo)) {
    refuse(servo + " is detached: it hears no " + std::string(what));
  }
  if (p.port.view.booting(p.servo)) {
    refuse(servo + " is booting: it hears no " + std::string(what) + " until it is up");
  }
  const wire::InstructionPacket packet{p.servo.protocol().value_or(wire::Protocol::V2),
                                       p.servo.id(), std::move(instruction)};
  const model::ServoResponse response = p.port.view.instruct(p.servo, packet);
  if (response.error != 0) {
    char error[8];
    std::snprintf(error, sizeof error, "0x%02X", response.error);
    refuse(servo + " refuses " + std::string(what) + ": its status would carry error " + error);
  }
  return {{"servo", p.servo.id()},
          {"attached", p.port.view.attached(p.servo)},
          {"booting", p.port.view.booting(p.servo)}};
}

ordered_json attached_json(const Plugged& p) {
  return {{"attached", p.port.view.attached(p.servo)}, {"booting", p.port.view.booting(p.servo)}};
}

}  // namespace

ordered_json protocol_json(wire::Protocol protocol) {
  if (const int number = wire::protocol_number(protocol); number != 0) {
    return number;
  }
  return wire::protocol_name(protocol);
}

ordered_json list(Target& target, const Args& /*args*/) {
  ordered_json ports = ordered_json::array();
  for (const auto& name : target.port_names()) {
    PortView* view = target.port(name);
    if (view == nullptr) {
      continue;
    }
    view->catch_up();
    ordered_json port = {{"name", name}};
    const nlohmann::json info = target.port_info(name);
    if (info.is_object()) {
      for (const auto& [key, value] : info.items()) {
        if (key != "name" && key != "servos") {
          port[key] = value;
        }
      }
    }
    ordered_json servos = ordered_json::array();
    for (const model::Servo* servo : view->servos()) {
      servos.push_back(servo_summary(*servo));
      servos.back()["attached"] = view->attached(*servo);
    }
    port["servos"] = std::move(servos);
    ports.push_back(std::move(port));
  }
  return {{"ports", std::move(ports)}};
}

ordered_json stats(Target& target, const Args& args) {
  ordered_json out = ordered_json::object();
  if (args.has("port")) {
    const Port port = port_of(target, args);
    out[port.name] = stats_json(port.view);
    return out;
  }
  for (const auto& name : target.port_names()) {
    if (const PortView* view = target.port(name)) {
      out[name] = stats_json(*view);
    }
  }
  return out;
}

ordered_json servo_detach(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  if (!p.port.view.attached(p.servo)) {
    refuse("servo " + std::to_string(p.servo.id()) + " on " + p.port.name + " is already detached");
  }
  p.port.view.detach(p.servo);
  return attached_json(p);
}

ordered_json servo_attach(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  if (p.port.view.attached(p.servo)) {
    refuse("servo " + std::to_string(p.servo.id()) + " on " + p.port.name +
           " is attached (servo.power_cycle restarts it)");
  }
  p.port.view.power_on(p.servo);
  return attached_json(p);
}

ordered_json servo_power_cycle(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  p.port.view.power_on(p.servo);
  return attached_json(p);
}

ordered_json servo_reboot(Target& target, const Args& args) {
  return instruct(plugged(target, args), wire::Reboot{}, "Reboot");
}

ordered_json servo_factory_reset(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  const std::string keep = args.string("keep").value_or("none");
  std::uint8_t option = wire::factory_reset::kResetAll;
  if (keep == "id") {
    option = wire::factory_reset::kResetAllButId;
  } else if (keep == "id_baud") {
    option = wire::factory_reset::kResetAllButIdAndBaud;
  } else if (keep != "none") {
    refuse("\"keep\" must be \"none\", \"id\" or \"id_baud\", not " + json_quoted(keep));
  }
  // Modbus RTU has no Factory Reset (nor Reboot): the control API resets a servo speaking it
  // device-side as the model's own firmware does over 2.0, options included (DYNAMIXEL-P);
  // Protocol Type goes back to its factory value with the rest (docs/control-api.md).
  const auto protocol = p.servo.protocol();
  const bool has_options =
      protocol == wire::Protocol::V2 ||
      (protocol == wire::Protocol::Modbus && p.servo.spec().speaks(wire::Protocol::V2));
  if (option != wire::factory_reset::kResetAll && !has_options) {
    refuse("servo " + std::to_string(p.servo.id()) + " on " + p.port.name +
           " does not speak Protocol 2.0, whose Factory Reset alone can keep the ID or baud");
  }
  return instruct(p, wire::FactoryReset{option}, "Factory Reset");
}

}  // namespace dxlemu::control
