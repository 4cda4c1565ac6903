#include "control/api.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "control/fault_commands.hpp"
#include "control/request.hpp"
#include "control/scenario.hpp"
#include "control/trace_commands.hpp"
#include "model/servo.hpp"

namespace dxlemu::control {
namespace {

// Deeper nesting is refused while parsing: destroying a request and dumping an echoed "id" are
// recursive, and a line of brackets must not exhaust the stack.
constexpr int kMaxDepth = 32;
// A parser message quotes what it read: a runaway string is cut to this many characters.
constexpr std::size_t kMaxParseMessage = 200;
// The widest value get and set handle by address (the widest control-table item).
constexpr std::int64_t kMaxValueBytes = 4;
constexpr int kBitsPerByte = 8;
constexpr std::uint8_t kByteMask = 0xFF;
// Sane surroundings for condition.set (units: °C, V, N·m). Nothing a real servo survives lies
// outside them, and the motor model's arithmetic stays finite within them.
constexpr int kMinAmbientC = -50;
constexpr int kMaxAmbientC = 200;
constexpr int kMinSupplyV = 0;
constexpr int kMaxSupplyV = 100;
constexpr int kMaxLoadNm = 1000;
constexpr double kNsPerMs = 1e6;
constexpr double kNsPerUs = 1e3;

std::size_t item_named(const model::ModelSpec& spec, const std::string& key) {
  const auto index = spec.index_of(key);
  if (!index) {
    refuse(spec.name + " has no item " + json_quoted(key));
  }
  return *index;
}

struct ByteRange {
  std::int64_t address = 0;
  std::int64_t size = 0;
};

std::string range_text(const ByteRange& range) {
  return "address " + std::to_string(range.address) + " size " + std::to_string(range.size);
}

/// The "address" and "size" of a request, within `spec`'s control table.
ByteRange byte_range(const Args& args, const model::ModelSpec& spec) {
  if (!args.has("address") && !args.has("size")) {
    refuse(std::string(args.command()) + " needs \"item\", or \"address\" and \"size\"");
  }
  const ByteRange range{args.required_integer("address"), args.required_integer("size")};
  if (range.size < 1 || range.size > kMaxValueBytes) {
    refuse("\"size\" must be 1 ~ " + std::to_string(kMaxValueBytes));
  }
  const auto table_size = static_cast<std::int64_t>(spec.table_size());
  if (range.address < 0 || range.address + range.size > table_size) {
    refuse(range_text(range) + " is outside the control table of " + spec.name + " (0 ~ " +
           std::to_string(table_size - 1) + ")");
  }
  return range;
}

/// The item a request names: by "item", or by an address range that is exactly one item.
std::size_t item_of(const Args& args, const model::ModelSpec& spec) {
  if (const auto key = args.string("item")) {
    if (args.has("address") || args.has("size")) {
      refuse("give \"item\" or \"address\" and \"size\", not both");
    }
    return item_named(spec, *key);
  }
  const ByteRange range = byte_range(args, spec);
  for (std::size_t i = 0; i < spec.items.size(); ++i) {
    const model::ItemSpec& item = spec.items[i];
    if (item.address == range.address) {
      if (item.size == range.size) {
        return i;
      }
      refuse(range_text(range) + " is not exactly one item of " + spec.name + ": " + item.key +
             " at " + std::to_string(item.address) + " is " + byte_count(item.size));
    }
  }
  refuse(range_text(range) + " is not exactly one item of " + spec.name);
}

// --- commands ------------------------------------------------------------------------------------

/// The key state of a servo that `list` shows, each only when the model has the item.
struct SummaryItem {
  std::string_view field;
  std::string_view item;
  bool boolean;
};
constexpr std::array<SummaryItem, 5> kSummaryItems = {{
    {"torque", "torque_enable", true},
    {"present_position", "present_position", false},
    {"present_temperature", "present_temperature", false},
    {"hardware_error_status", "hardware_error_status", false},
    {"moving", "moving", true},
}};

ordered_json servo_summary(const model::Servo& servo) {
  const auto protocol = servo.protocol();
  ordered_json out = {
      {"id", servo.id()},
      {"model", servo.spec().name},
      {"protocol", protocol ? ordered_json(static_cast<int>(*protocol)) : ordered_json(nullptr)},
      {"baud", servo.baud_bps()},
  };
  for (const SummaryItem& summary : kSummaryItems) {
    if (const auto index = servo.spec().index_of(summary.item)) {
      const std::int64_t value = servo.table().get(*index);
      if (summary.boolean) {
        out[std::string(summary.field)] = value != 0;
      } else {
        out[std::string(summary.field)] = value;
      }
    }
  }
  return out;
}

ordered_json list(Target& target, const Args& /*args*/) {
  ordered_json ports = ordered_json::array();
  for (const auto& name : target.port_names()) {
    bus::Bus* bus = target.bus(name);
    if (bus == nullptr) {
      continue;
    }
    bus->catch_up();
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
    for (const auto& servo : bus->servos()) {
      servos.push_back(servo_summary(*servo));
      servos.back()["attached"] = bus->attached(*servo);
    }
    port["servos"] = std::move(servos);
    ports.push_back(std::move(port));
  }
  return {{"ports", std::move(ports)}};
}

ordered_json get(Target& target, const Args& args) {
  const model::Servo& servo = addressed(target, args);
  const model::ModelSpec& spec = servo.spec();
  if (args.has("item")) {
    const std::size_t index = item_of(args, spec);
    return {{"item", spec.items[index].key}, {"value", servo.table().get(index)}};
  }
  // Device side: the image as it is, without access rules, read hooks or Indirect Data mapping.
  const ByteRange range = byte_range(args, spec);
  const auto bytes = servo.table().bytes().subspan(static_cast<std::size_t>(range.address),
                                                   static_cast<std::size_t>(range.size));
  std::uint64_t value = 0;
  for (auto byte = bytes.rbegin(); byte != bytes.rend(); ++byte) {
    value = (value << kBitsPerByte) | *byte;  // little-endian, as on the wire
  }
  return {{"address", range.address},
          {"size", range.size},
          {"value", value},
          {"bytes", std::vector<std::uint8_t>(bytes.begin(), bytes.end())}};
}

bool fits(const model::ItemSpec& item, std::int64_t value) {
  const int bits = kBitsPerByte * item.size;
  const std::int64_t lo = item.is_signed ? -(std::int64_t{1} << (bits - 1)) : 0;
  const std::int64_t hi =
      item.is_signed ? (std::int64_t{1} << (bits - 1)) - 1 : (std::int64_t{1} << bits) - 1;
  return value >= lo && value <= hi;
}

bool is_indirect_data(const model::ModelSpec& spec, const model::ItemSpec& item) {
  return std::any_of(spec.indirect.begin(), spec.indirect.end(), [&](const auto& block) {
    return item.address >= block.data && item.address < block.data + block.count;
  });
}

/// Items whose new value a servo applies only at commit_deferred() (identity on the bus).
constexpr std::array<std::string_view, 5> kDeferredItems = {"id", "baud_rate", "return_delay_time",
                                                            "protocol_type", "protocol_version"};

/// Writes `value` (which fits the item) into `servo`'s item `index`.
void write_item(model::Servo& servo, std::size_t index, std::int64_t value) {
  model::ControlTable& table = servo.table();
  const model::ModelSpec& spec = servo.spec();
  const model::ItemSpec& item = spec.items[index];
  std::vector<std::uint8_t> bytes(item.size);
  const auto raw = static_cast<std::uint64_t>(value);  // two's complement, as ControlTable stores
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    bytes[i] = static_cast<std::uint8_t>((raw >> (kBitsPerByte * i)) & kByteMask);
  }
  // The bus's rules decide only whether the servo's behaviours hear of the change. A value that a
  // Write instruction could put there goes through bus_write, so its hooks run as after a real
  // Write (a goal starts a move, Torque Enable holds where the shaft is). Anything else (read-only
  // items, EEPROM while locked, values outside the item's range) is forced into the image, which
  // no hook hears. Indirect Data is always forced: a bus write would land at the mapped address.
  const wire::Protocol protocol = servo.protocol().value_or(
      spec.protocols.empty() ? wire::Protocol::V2 : spec.protocols.front());
  if (!is_indirect_data(spec, item) && table.check_write(item.address, bytes, protocol).ok()) {
    table.bus_write(item.address, bytes, protocol);
  } else {
    table.set(index, value);
  }
  // Present values set device-side move the shaft, the winding or the supply there.
  servo.motion().wake();
  if (std::find(kDeferredItems.begin(), kDeferredItems.end(), item.key) != kDeferredItems.end()) {
    servo.commit_deferred();
  }
}

ordered_json set(Target& target, const Args& args) {
  model::Servo& servo = addressed(target, args);
  const std::size_t index = item_of(args, servo.spec());
  const model::ItemSpec& item = servo.spec().items[index];
  const std::int64_t value = args.required_integer("value");
  if (!fits(item, value)) {
    refuse("value " + std::to_string(value) + " does not fit " + item.key + " (" +
           byte_count(item.size) + ")");
  }
  write_item(servo, index, value);
  return {{"item", item.key}, {"value", servo.table().get(index)}};
}

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
  port.bus.catch_up();
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
  for (const auto& servo : port.bus.servos()) {
    ordered_json entry = {{"id", servo->id()}};
    entry.update(change(*servo));
    all.push_back(std::move(entry));
  }
  return all;
}

ordered_json time_json(sim::SimTime t) {
  const std::int64_t ns = sim::ns_since_start(t);
  return {{"ns", ns}, {"ms", static_cast<double>(ns) / kNsPerMs}};
}

ordered_json clock_now(Target& target, const Args& /*args*/) {
  return time_json(target.now());
}

ordered_json clock_step(Target& target, const Args& args) {
  if (!target.manual_clock()) {
    refuse("clock.step needs --timing manual");
  }
  struct Unit {
    std::string_view key;
    double ns;
  };
  constexpr std::array<Unit, 3> kUnits = {{{"ms", kNsPerMs}, {"us", kNsPerUs}, {"ns", 1}}};
  std::optional<std::pair<Unit, double>> step;
  for (const Unit& unit : kUnits) {
    if (const auto value = args.number(unit.key)) {
      if (step) {
        refuse("clock.step takes only one of \"ms\", \"us\" or \"ns\"");
      }
      step.emplace(unit, *value);
    }
  }
  if (!step) {
    refuse("clock.step needs one of \"ms\", \"us\" or \"ns\"");
  }
  const auto& [unit, value] = *step;
  const double ns = std::round(value * unit.ns);
  if (!(value > 0)) {
    refuse(json_quoted(unit.key) + " must be positive");
  }
  if (ns < 1) {
    refuse(json_quoted(unit.key) + " must be at least 1 ns");
  }
  if (ns > static_cast<double>(kMaxStep.count())) {
    refuse("one clock.step moves at most " +
           std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(kMaxStep).count()) +
           " ms");
  }
  target.step_clock(sim::SimDuration{static_cast<std::int64_t>(ns)});
  return time_json(target.now());
}

ordered_json stats_json(const bus::BusStats& s) {
  return {{"bytes_in", s.bytes_in},           {"frames", s.frames},
          {"garbage_bytes", s.garbage_bytes}, {"bad_checks", s.bad_checks},
          {"truncated", s.truncated},         {"impossible_lengths", s.impossible_lengths},
          {"decode_errors", s.decode_errors}, {"replies", s.replies},
          {"unread_drops", s.unread_drops},   {"collisions", s.collisions},
          {"id_conflicts", s.id_conflicts},   {"faults_injected", s.faults_injected}};
}

ordered_json stats(Target& target, const Args& args) {
  ordered_json out = ordered_json::object();
  if (args.has("port")) {
    const Port port = port_of(target, args);
    out[port.name] = stats_json(port.bus.stats());
    return out;
  }
  for (const auto& name : target.port_names()) {
    if (const bus::Bus* bus = target.bus(name)) {
      out[name] = stats_json(bus->stats());
    }
  }
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
  port.bus.catch_up();
  return {port, servo_on(port, id)};
}

ordered_json attached_json(const Plugged& p) {
  return {{"attached", p.port.bus.attached(p.servo)}, {"booting", p.port.bus.booting(p.servo)}};
}

ordered_json servo_detach(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  if (!p.port.bus.attached(p.servo)) {
    refuse("servo " + std::to_string(p.servo.id()) + " on " + p.port.name + " is already detached");
  }
  p.port.bus.detach(p.servo);
  return attached_json(p);
}

ordered_json servo_attach(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  if (p.port.bus.attached(p.servo)) {
    refuse("servo " + std::to_string(p.servo.id()) + " on " + p.port.name +
           " is attached (servo.power_cycle restarts it)");
  }
  p.port.bus.power_on(p.servo);
  return attached_json(p);
}

ordered_json servo_power_cycle(Target& target, const Args& args) {
  const Plugged p = plugged(target, args);
  p.port.bus.power_on(p.servo);
  return attached_json(p);
}

ordered_json shutdown(Target& target, const Args& /*args*/) {
  target.request_shutdown();
  return ordered_json::object();
}

ordered_json help(Target& /*target*/, const Args& /*args*/) {
  return Api::command_names();
}

// --- the command table -----------------------------------------------------------------------

struct Command {
  std::string_view name;
  /// The arguments it takes besides "id" and "cmd"; any other is refused.
  std::vector<std::string_view> fields;
  ordered_json (*run)(Target& target, const Args& args);
};

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"list", {}, list},
      {"get", {"port", "servo", "item", "address", "size"}, get},
      {"set", {"port", "servo", "item", "address", "size", "value"}, set},
      {"condition.set",
       {"port", "servo", "ambient_temperature", "supply_voltage", "external_load", "blocked"},
       condition_set},
      {"servo.detach", {"port", "servo"}, servo_detach},
      {"servo.attach", {"port", "servo"}, servo_attach},
      {"servo.power_cycle", {"port", "servo"}, servo_power_cycle},
      {"fault.add", {"rule"}, fault_add},
      {"fault.list", {}, fault_list},
      {"fault.remove", {"rule"}, fault_remove},
      {"fault.clear", {}, fault_clear},
      {"scenario.load", {"file", "scenario"}, scenario_load},
      {"trace.subscribe", {"port"}, trace_subscribe},
      {"trace.unsubscribe", {}, trace_unsubscribe},
      {"clock.now", {}, clock_now},
      {"clock.step", {"ms", "us", "ns"}, clock_step},
      {"stats", {"port"}, stats},
      {"shutdown", {}, shutdown},
      {"help", {}, help},
  };
  return table;
}

const Command& command_for(const ordered_json& request) {
  const auto cmd = request.find("cmd");
  if (cmd == request.end()) {
    refuse("\"cmd\" is required (commands: " + joined(Api::command_names()) + ")");
  }
  if (!cmd->is_string()) {
    refuse("\"cmd\" must be a string");
  }
  const auto& name = cmd->get_ref<const std::string&>();
  const auto& table = commands();
  const auto found = std::find_if(table.begin(), table.end(),
                                  [&](const Command& command) { return command.name == name; });
  if (found == table.end()) {
    refuse("unknown command " + json_quoted(name) + " (commands: " + joined(Api::command_names()) +
           ")");
  }
  return *found;
}

void check_fields(const ordered_json& request, const Command& command) {
  for (const auto& [key, value] : request.items()) {
    if (key == "id" || key == "cmd" ||
        std::find(command.fields.begin(), command.fields.end(), key) != command.fields.end()) {
      continue;
    }
    std::string takes;
    for (const auto field : command.fields) {
      takes += (takes.empty() ? "" : ", ") + std::string(field);
    }
    refuse("unknown field " + json_quoted(key) + " for " + std::string(command.name) +
           " (it takes " + (takes.empty() ? "no arguments" : takes) + ")");
  }
}

ordered_json parse(std::string_view line) {
  const ordered_json::parser_callback_t limit_depth =
      [](int depth, ordered_json::parse_event_t /*event*/, ordered_json& /*parsed*/) {
        if (depth > kMaxDepth) {
          refuse("the request nests deeper than " + std::to_string(kMaxDepth) + " levels");
        }
        return true;
      };
  try {
    return ordered_json::parse(line.begin(), line.end(), limit_depth);
  } catch (const ordered_json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    // what() is "[json.exception.parse_error.101] parse error at ...": keep from "parse error".
    std::string text = e.what();
    if (const auto start = text.find("] "); start != std::string::npos) {
      text.erase(0, start + 2);
    }
    if (text.size() > kMaxParseMessage) {
      text.resize(kMaxParseMessage);
      text += "...";
    }
    refuse("not valid JSON: " + text);
  }
}

}  // namespace

Api::Api(Target& target) : target_(target) {}

std::vector<std::string> Api::command_names() {
  std::vector<std::string> names;
  for (const Command& command : commands()) {
    names.emplace_back(command.name);
  }
  return names;
}

std::string Api::handle(std::string_view line, std::uint64_t client) {
  ordered_json request;
  try {
    request = parse(line);
  } catch (const Refusal& e) {
    return dumped({{"id", nullptr}, {"ok", false}, {"error", e.what()}});
  }
  return dumped(run(request, client));
}

ordered_json Api::run(const ordered_json& request, std::uint64_t client) {
  ordered_json reply = {{"id", nullptr}};
  try {
    if (!request.is_object()) {
      refuse("a request must be a JSON object, e.g. {\"id\":1,\"cmd\":\"list\"}");
    }
    if (const auto id = request.find("id"); id != request.end()) {
      reply["id"] = *id;
    }
    const Command& command = command_for(request);
    check_fields(request, command);
    ordered_json result = command.run(target_, Args(request, command.name, client));
    reply["ok"] = true;
    reply["result"] = std::move(result);
  } catch (const Refusal& e) {
    reply["ok"] = false;
    reply["error"] = e.what();
  } catch (const std::exception& e) {
    // Our own bug (or memory exhaustion): say so rather than drop the connection.
    reply["ok"] = false;
    reply["error"] = std::string("internal error: ") + e.what();
  }
  return reply;
}

std::optional<std::string> Api::check(Target& target, const ordered_json& request) {
  try {
    if (!request.is_object()) {
      refuse("a request must be a JSON object");
    }
    const Command& command = command_for(request);
    check_fields(request, command);
    const Args args(request, command.name);
    if (args.has("servo")) {
      servo_on(port_of(target, args), args.required_integer("servo"));
    } else if (args.has("port")) {
      port_of(target, args);
    }
    if (command.name == "fault.add") {
      rule_of(target, args.value("rule"));
    }
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

}  // namespace dxlemu::control
