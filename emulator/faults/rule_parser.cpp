#include "faults/rule_parser.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include "wire/protocol.hpp"

namespace dxlemu::faults {

using nlohmann::json;
using nlohmann::ordered_json;

namespace {

constexpr std::int64_t kMaxId = 252;
// Long enough for any test; short enough that a typo in units does not hang a bus for hours.
constexpr std::int64_t kMaxDelayUs = 10'000'000;
constexpr std::int64_t kMaxBytes = 1024;
// ATmega8 (AX-12's controller): an EEPROM byte takes 8.5 ms to program (datasheet, "EEPROM
// write"); the servo does not listen meanwhile.
constexpr std::int64_t kDefaultUsPerByte = 8500;
constexpr std::size_t kDefaultGarbage = 4;
constexpr std::size_t kDefaultNoise = 8;

std::string member(const std::string& name) {
  return "/" + name;
}

std::int64_t integer(const json& value, const std::string& pointer, std::int64_t lo,
                     std::int64_t hi) {
  if (value.is_number_unsigned()) {
    const auto u = value.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(hi) && static_cast<std::int64_t>(u) >= lo) {
      return static_cast<std::int64_t>(u);
    }
  } else if (value.is_number_integer()) {
    const auto i = value.get<std::int64_t>();
    if (i >= lo && i <= hi) {
      return i;
    }
  }
  throw RuleError(pointer, "must be an integer from " + std::to_string(lo) + " to " +
                               std::to_string(hi) + ", not " + value.dump());
}

double number(const json& value, const std::string& pointer, double lo, double hi) {
  if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < lo ||
      value.get<double>() > hi) {
    const auto text = [](double x) {
      std::ostringstream out;
      out << x;
      return out.str();
    };
    throw RuleError(
        pointer, "must be a number from " + text(lo) + " to " + text(hi) + ", not " + value.dump());
  }
  return value.get<double>();
}

sim::SimDuration milliseconds(const json& value, const std::string& pointer) {
  const double ms = number(value, pointer, 0, 1e9);
  return sim::SimDuration(static_cast<std::int64_t>(std::llround(ms * 1e6)));
}

sim::SimDuration microseconds(const json& value, const std::string& pointer) {
  return std::chrono::microseconds(integer(value, pointer, 0, kMaxDelayUs));
}

// A member that may be one value or an array of them.
std::vector<std::pair<const json*, std::string>> one_or_many(const json& value,
                                                             const std::string& pointer) {
  std::vector<std::pair<const json*, std::string>> out;
  if (value.is_array()) {
    if (value.empty()) {
      throw RuleError(pointer, "must not be empty (leave it out to match everything)");
    }
    for (std::size_t i = 0; i < value.size(); ++i) {
      out.emplace_back(&value[i], pointer + "/" + std::to_string(i));
    }
  } else {
    out.emplace_back(&value, pointer);
  }
  return out;
}

// Every instruction name a rule may match, each once, protocol by protocol in the table's order
// (DYNAMIXEL's, then FEETECH's own): every instruction but a status marker.
std::vector<std::string_view> known_instruction_names() {
  std::vector<std::string_view> names;
  for (const wire::ProtocolTraits& row : wire::kProtocolTable) {
    for (const wire::InstructionInfo& info : row.instructions) {
      if (info.role != wire::InstructionRole::Status &&
          std::find(names.begin(), names.end(), info.name) == names.end()) {
        names.push_back(info.name);
      }
    }
  }
  return names;
}

bool is_instruction_name(std::string_view name) {
  const auto names = known_instruction_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string instruction_names() {
  std::string out;
  for (const std::string_view name : known_instruction_names()) {
    out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out;
}

Match parse_match(const json& value) {
  const std::string base = "/match";
  if (!value.is_object()) {
    throw RuleError(base, "must be an object with port, servos, instruction or address");
  }
  Match match;
  for (const auto& [key, v] : value.items()) {
    const std::string pointer = base + "/" + key;
    if (key == "port") {
      if (!v.is_string() || v.get<std::string>().empty()) {
        throw RuleError(pointer, "must be a port name (a string)");
      }
      match.port = v.get<std::string>();
    } else if (key == "servos") {
      for (const auto& [id, p] : one_or_many(v, pointer)) {
        match.servos.push_back(static_cast<std::uint8_t>(integer(*id, p, 0, kMaxId)));
      }
    } else if (key == "instruction") {
      for (const auto& [name, p] : one_or_many(v, pointer)) {
        if (!name->is_string() || !is_instruction_name(name->get<std::string>())) {
          throw RuleError(p, "must be an instruction name: " + instruction_names());
        }
        match.instructions.push_back(name->get<std::string>());
      }
    } else if (key == "address") {
      if (v.is_array()) {
        if (v.size() != 2) {
          throw RuleError(pointer, "must be an address or [first, last]");
        }
        const auto first = integer(v[0], pointer + "/0", 0, 0xFFFF);
        const auto last = integer(v[1], pointer + "/1", 0, 0xFFFF);
        if (last < first) {
          throw RuleError(pointer, "last address comes before the first");
        }
        match.address = {static_cast<std::uint16_t>(first), static_cast<std::uint16_t>(last)};
      } else {
        const auto a = static_cast<std::uint16_t>(integer(v, pointer, 0, 0xFFFF));
        match.address = {a, a};
      }
    } else {
      throw RuleError(pointer, "unknown member (match takes port, servos, instruction, address)");
    }
  }
  return match;
}

// The parameters each action takes, besides action, match and the triggers.
std::set<std::string> parameters_of(Action action) {
  switch (action) {
    case Action::DelayReply:
    case Action::Slow:
      return {"us"};
    case Action::FlipBits:
      return {"bits"};
    case Action::TruncateReply:
    case Action::Noise:
      return {"bytes"};
    case Action::GarbageBefore:
      return {"bytes", "data"};
    case Action::WrongId:
      return {"id"};
    case Action::HardwareError:
      return {"kind"};
    case Action::EepromBusy:
      return {"us_per_byte"};
    case Action::ModbusException:
      return {"code"};
    default:
      return {};
  }
}

std::string fault_kinds() {
  std::string out;
  for (const auto f : {model::HardwareFault::Overheating, model::HardwareFault::Overload,
                       model::HardwareFault::InputVoltage, model::HardwareFault::ElectricalShock,
                       model::HardwareFault::Encoder, model::HardwareFault::HallSensor}) {
    out += (out.empty() ? "" : ", ") + std::string(model::fault_name(f));
  }
  return out;
}

void parse_parameter(Rule& rule, const std::string& key, const json& v) {
  const std::string pointer = member(key);
  if (key == "us") {
    rule.delay = microseconds(v, pointer);
  } else if (key == "bits") {
    rule.bits = static_cast<std::uint32_t>(integer(v, pointer, 1, 64));
  } else if (key == "bytes") {
    rule.bytes = static_cast<std::size_t>(
        integer(v, pointer, rule.action == Action::TruncateReply ? 0 : 1, kMaxBytes));
  } else if (key == "data") {
    if (!v.is_array() || v.empty() || v.size() > kMaxBytes) {
      throw RuleError(pointer, "must be an array of 1 to 1024 bytes");
    }
    for (std::size_t i = 0; i < v.size(); ++i) {
      rule.data.push_back(
          static_cast<std::uint8_t>(integer(v[i], pointer + "/" + std::to_string(i), 0, 255)));
    }
  } else if (key == "id") {
    rule.id = static_cast<std::uint8_t>(integer(v, pointer, 0, 0xFD));
  } else if (key == "kind") {
    const auto kind = v.is_string() ? model::fault_from_name(v.get<std::string>()) : std::nullopt;
    if (!kind) {
      throw RuleError(pointer, "must be one of " + fault_kinds());
    }
    rule.kind = *kind;
  } else if (key == "us_per_byte") {
    rule.per_byte = microseconds(v, pointer);
  } else if (key == "code") {
    // Any code a one-byte exception field carries: 01 ~ 04 are what a DYNAMIXEL sends, the
    // others test how a master takes the rest (05 Acknowledge, 06 Busy, 0B Gateway...).
    rule.code = static_cast<std::uint8_t>(integer(v, pointer, 1, 0xFF));
  }
}

}  // namespace

Rule parse_rule(const json& value) {
  if (!value.is_object()) {
    throw RuleError("", "a rule must be a JSON object with at least \"action\"");
  }
  const auto action_member = value.find("action");
  if (action_member == value.end()) {
    throw RuleError("/action", "missing: say what the rule does (e.g. \"drop_reply\")");
  }
  const auto action = action_member->is_string()
                          ? action_from_name(action_member->get<std::string>())
                          : std::nullopt;
  if (!action) {
    std::string names;
    for (const Action a : all_actions()) {
      names += (names.empty() ? "" : ", ") + std::string(action_name(a));
    }
    throw RuleError("/action", "must be one of " + names);
  }
  Rule rule;
  rule.action = *action;
  if (rule.action == Action::EepromBusy) {
    rule.per_byte = std::chrono::microseconds(kDefaultUsPerByte);
  }
  const std::set<std::string> parameters = parameters_of(rule.action);
  // A state fault is on or off over time: it has no packets to count or to draw for.
  const std::set<std::string> packet_triggers = {"probability", "count", "after"};
  for (const auto& [key, v] : value.items()) {
    const std::string pointer = member(key);
    if (key == "action") {
      continue;
    }
    if (is_state_fault(rule.action) && packet_triggers.contains(key)) {
      throw RuleError(pointer, std::string(action_name(rule.action)) +
                                   " is a state of the servo, not a packet event: it takes "
                                   "match.port, match.servos, from_ms and until_ms");
    }
    if (key == "match") {
      rule.match = parse_match(v);
      if (is_state_fault(rule.action) && (!rule.match.instructions.empty() || rule.match.address)) {
        throw RuleError("/match", std::string(action_name(rule.action)) +
                                      " matches servos only (port and servos)");
      }
    } else if (key == "probability") {
      rule.trigger.probability = number(v, pointer, 0, 1);
    } else if (key == "count") {
      rule.trigger.count = static_cast<std::uint64_t>(integer(v, pointer, 1, INT64_MAX));
    } else if (key == "after") {
      rule.trigger.after = static_cast<std::uint64_t>(integer(v, pointer, 0, INT64_MAX));
    } else if (key == "from_ms") {
      rule.trigger.from = milliseconds(v, pointer);
    } else if (key == "until_ms") {
      rule.trigger.until = milliseconds(v, pointer);
    } else if (parameters.contains(key)) {
      parse_parameter(rule, key, v);
    } else {
      std::string takes;
      for (const std::string& p : parameters) {
        takes += ", " + p;
      }
      throw RuleError(pointer, "unknown member for " + std::string(action_name(rule.action)) +
                                   " (it takes match, probability, count, after, from_ms, "
                                   "until_ms" +
                                   takes + ")");
    }
  }
  if (rule.trigger.until && *rule.trigger.until <= rule.trigger.from) {
    throw RuleError("/until_ms", "must be later than from_ms");
  }
  if ((rule.action == Action::DelayReply || rule.action == Action::Slow) && !value.contains("us")) {
    throw RuleError("/us", "missing: how many microseconds to add");
  }
  if (rule.action == Action::HardwareError && !value.contains("kind")) {
    throw RuleError("/kind", "missing: which hardware error (" + fault_kinds() + ")");
  }
  if (rule.action == Action::GarbageBefore && !rule.data.empty() && rule.bytes) {
    throw RuleError("/bytes", "give either data or bytes, not both");
  }
  if (rule.action == Action::GarbageBefore && rule.data.empty() && !rule.bytes) {
    rule.bytes = kDefaultGarbage;
  }
  if (rule.action == Action::Noise && !rule.bytes) {
    rule.bytes = kDefaultNoise;
  }
  return rule;
}

ordered_json rule_json(const Rule& rule) {
  ordered_json out;
  out["action"] = action_name(rule.action);
  ordered_json match = ordered_json::object();
  if (rule.match.port) {
    match["port"] = *rule.match.port;
  }
  if (!rule.match.servos.empty()) {
    match["servos"] = rule.match.servos;
  }
  if (!rule.match.instructions.empty()) {
    ordered_json names = ordered_json::array();
    for (const std::string& name : rule.match.instructions) {
      names.push_back(name);
    }
    match["instruction"] = names;
  }
  if (rule.match.address) {
    match["address"] = {rule.match.address->first, rule.match.address->second};
  }
  out["match"] = match;
  const auto ms = [](sim::SimDuration d) { return static_cast<double>(d.count()) / 1e6; };
  if (!is_state_fault(rule.action)) {
    out["probability"] = rule.trigger.probability;
    if (rule.trigger.count) {
      out["count"] = *rule.trigger.count;
    }
    out["after"] = rule.trigger.after;
  }
  out["from_ms"] = ms(rule.trigger.from);
  if (rule.trigger.until) {
    out["until_ms"] = ms(*rule.trigger.until);
  }
  const auto us = [](sim::SimDuration d) {
    return std::chrono::duration_cast<std::chrono::microseconds>(d).count();
  };
  switch (rule.action) {
    case Action::DelayReply:
    case Action::Slow:
      out["us"] = us(rule.delay);
      break;
    case Action::FlipBits:
      out["bits"] = rule.bits;
      break;
    case Action::TruncateReply:
    case Action::Noise:
      if (rule.bytes) {
        out["bytes"] = *rule.bytes;
      }
      break;
    case Action::GarbageBefore:
      if (rule.data.empty()) {
        out["bytes"] = *rule.bytes;
      } else {
        out["data"] = rule.data;
      }
      break;
    case Action::WrongId:
      if (rule.id) {
        out["id"] = *rule.id;
      }
      break;
    case Action::HardwareError:
      out["kind"] = model::fault_name(rule.kind);
      break;
    case Action::EepromBusy:
      out["us_per_byte"] = us(rule.per_byte);
      break;
    case Action::ModbusException:
      out["code"] = rule.code;
      break;
    default:
      break;
  }
  return out;
}

}  // namespace dxlemu::faults
