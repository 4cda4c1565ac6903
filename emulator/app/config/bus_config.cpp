#include "app/config/bus_config.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "app/config/hand_start.hpp"
#include "bus/usb_adapter_link.hpp"

namespace dxlemu::app {
namespace {

using nlohmann::json;

struct AdapterChip {
  const char* name;
  std::size_t packet_data;
};
// FTDI AN232B-04: a full-speed chip's USB packet is 64 bytes, a high-speed one's 512; 2 of each
// are the modem status.
constexpr std::array<AdapterChip, 2> kAdapterChips{{
    {"ft232h", bus::kHighSpeedPacketData},
    {"ft232r", bus::kFullSpeedPacketData},
}};

// RFC 6901: "~" and "/" inside a reference token are escaped.
std::string pointer_token(const std::string& key) {
  std::string out;
  for (const char c : key) {
    out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  }
  return out;
}

// Walks a config document, refusing the first problem with its JSON pointer.
class ConfigParser {
 public:
  ConfigParser(std::string origin, const ModelLibrary& library)
      : origin_(std::move(origin)), library_(library) {}

  BusConfig parse(const std::string& text) {
    const json doc = parse_json(text, origin_);
    object(doc, "", {"ports", "robot", "physics", "description"});
    BusConfig config;
    if (doc.contains("robot")) {
      config.robot = parse_robot(doc["robot"], "/robot");
    }
    const json& ports = member(doc, "", "ports");
    if (!ports.is_array() || ports.empty()) {
      fail("/ports", "must be a non-empty array of ports");
    }
    std::set<std::string> names;
    std::set<std::string> links;
    for (std::size_t i = 0; i < ports.size(); ++i) {
      const std::string at = "/ports/" + std::to_string(i);
      PortConfig port = parse_port(ports[i], at);
      if (!names.insert(port.name).second) {
        fail(at + "/name", "port name \"" + port.name + "\" is used twice");
      }
      if (port.link && !links.insert(port.link->lexically_normal().string()).second) {
        fail(at + "/link", "link " + port.link->string() + " is used twice");
      }
      config.ports.push_back(std::move(port));
    }
    if (doc.contains("physics")) {
      config.physics = parse_physics(doc["physics"], origin_, config.ports);
    }
    return config;
  }

 private:
  [[noreturn]] void fail(const std::string& pointer, const std::string& reason) const {
    throw ConfigError(origin_, pointer, reason);
  }

  // `value` must be an object whose keys are all in `allowed`.
  void object(const json& value, const std::string& at,
              std::initializer_list<const char*> allowed) {
    if (!value.is_object()) {
      fail(at, "must be an object");
    }
    for (const auto& member : value.items()) {
      const std::string& key = member.key();
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
        std::string list;
        for (const char* a : allowed) {
          list += (list.empty() ? "" : ", ") + std::string(a);
        }
        fail(at + "/" + pointer_token(key), "unknown field (allowed: " + list + ")");
      }
    }
  }

  const json& member(const json& value, const std::string& at, const char* key) {
    if (!value.contains(key)) {
      fail(at + "/" + key, "is required");
    }
    return value.at(key);
  }

  std::string string(const json& value, const std::string& at) {
    if (!value.is_string() || value.get<std::string>().empty()) {
      fail(at, "must be a non-empty string");
    }
    return value.get<std::string>();
  }

  std::int64_t integer(const json& value, const std::string& at, std::int64_t min,
                       std::int64_t max) {
    if (!value.is_number_integer()) {
      fail(at, "must be an integer");
    }
    // Unsigned JSON numbers beyond int64 are out of any range we accept.
    if (value.is_number_unsigned() &&
        value.get<std::uint64_t>() > static_cast<std::uint64_t>(max)) {
      fail(at, value.dump() + " is outside " + std::to_string(min) + " ~ " + std::to_string(max));
    }
    const auto v = value.get<std::int64_t>();
    if (v < min || v > max) {
      fail(at,
           std::to_string(v) + " is outside " + std::to_string(min) + " ~ " + std::to_string(max));
    }
    return v;
  }

  // A list of non-empty strings at `at`, or one string (a list of one) when `one_allowed`.
  std::vector<std::string> strings(const json& value, const std::string& at, bool one_allowed) {
    if (one_allowed && value.is_string()) {
      return {string(value, at)};
    }
    if (!value.is_array() || value.empty()) {
      fail(at, one_allowed ? "must be a non-empty string or array of strings"
                           : "must be a non-empty array of strings");
    }
    std::vector<std::string> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      out.push_back(string(value[i], at + "/" + std::to_string(i)));
    }
    return out;
  }

  // A robot's name at `at`: typed on command lines and a profile's file name, so lowercase and
  // plain.
  std::string robot_name(const json& value, const std::string& at) {
    std::string name = string(value, at);
    const bool plain = std::all_of(name.begin(), name.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
    });
    if (!plain || name.size() > kMaxRobotName || name.front() == '.') {
      fail(at, "must be 1 to 40 lowercase letters, digits, '_', '.' or '-', not starting with '.'");
    }
    return name;
  }

  // The header of a robot profile (docs/robots.md "Header").
  RobotHeader parse_robot(const json& value, const std::string& at) {
    object(value, at,
           {"name", "title", "sources", "software", "notes", "role", "pairs_with", "description"});
    RobotHeader robot;
    robot.name = robot_name(member(value, at, "name"), at + "/name");
    robot.title = string(member(value, at, "title"), at + "/title");
    robot.sources = strings(member(value, at, "sources"), at + "/sources", false);
    for (std::size_t i = 0; i < robot.sources.size(); ++i) {
      const std::string& url = robot.sources[i];
      if (url.rfind("https://", 0) != 0 && url.rfind("http://", 0) != 0) {
        fail(at + "/sources/" + std::to_string(i),
             "must be a URL (https://...) of the public file the facts come from");
      }
    }
    if (value.contains("software")) {
      robot.software = string(value["software"], at + "/software");
    }
    if (value.contains("notes")) {
      robot.notes = strings(value["notes"], at + "/notes", true);
    }
    if (value.contains("role")) {
      const std::string role = string(value["role"], at + "/role");
      for (const RobotRole r : {RobotRole::Leader, RobotRole::Follower}) {
        if (role == robot_role_name(r)) {
          robot.role = r;
        }
      }
      if (!robot.role) {
        fail(at + "/role", "must be \"leader\" or \"follower\"");
      }
    }
    if (value.contains("pairs_with")) {
      // Which robot the pair's other half is, is checked when every profile is loaded
      // (RobotLibrary::load): a user's directory may add or replace it.
      if (!robot.role) {
        fail(at + "/pairs_with", "needs \"role\": a pair is a leader and a follower");
      }
      robot.pairs_with = robot_name(value["pairs_with"], at + "/pairs_with");
      if (robot.pairs_with == robot.name) {
        fail(at + "/pairs_with", "must name another robot's profile, not this one");
      }
    }
    return robot;
  }

  double number(const json& value, const std::string& at) {
    if (!value.is_number() || !std::isfinite(value.get<double>())) {
      fail(at, "must be a number");
    }
    return value.get<double>();
  }

  // "joints" of a port whose servos are parsed: names the robot's software gives them.
  std::vector<JointName> parse_joints(const json& value, const std::string& at,
                                      const PortConfig& port) {
    if (!value.is_array()) {
      fail(at, "must be an array of joints");
    }
    std::vector<JointName> joints;
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string joint_at = at + "/" + std::to_string(i);
      JointName joint = parse_joint(value[i], joint_at, port);
      for (const JointName& other : joints) {
        if (other.name == joint.name) {
          fail(joint_at + "/name", "joint name \"" + joint.name + "\" is used twice on this port");
        }
        if (other.id == joint.id) {
          fail(joint_at + "/id", "servo " + std::to_string(joint.id) + " is joint \"" + other.name +
                                     "\" already: one joint per servo");
        }
      }
      joints.push_back(std::move(joint));
    }
    return joints;
  }

  JointName parse_joint(const json& value, const std::string& at, const PortConfig& port) {
    object(value, at, {"name", "id", "range_deg", "description"});
    JointName joint;
    joint.name = string(member(value, at, "name"), at + "/name");
    // Names are keys of control-API requests and trajectory columns, where a column may also
    // name a servo by its decimal ID: plain, and never all digits.
    const bool plain = std::all_of(joint.name.begin(), joint.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
    });
    const bool digits = std::all_of(joint.name.begin(), joint.name.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c)) != 0;
    });
    if (!plain || joint.name.size() > kMaxJointName) {
      fail(at + "/name", "must be 1 to 40 letters, digits, '_', '-' or '.'");
    }
    if (digits) {
      fail(at + "/name", "must not be all digits (a number names a servo by its ID)");
    }
    joint.id =
        static_cast<std::uint8_t>(integer(member(value, at, "id"), at + "/id", 0, kMaxServoId));
    if (std::none_of(port.servos.begin(), port.servos.end(),
                     [&](const ServoConfig& s) { return s.id == joint.id; })) {
      fail(at + "/id", "port " + port.name + " has no servo " + std::to_string(joint.id));
    }
    if (value.contains("range_deg")) {
      const json& range = value["range_deg"];
      const std::string range_at = at + "/range_deg";
      if (!range.is_array() || range.size() != 2) {
        fail(range_at, "must be [low, high] in degrees");
      }
      std::array<double, 2> ends{};
      for (std::size_t i = 0; i < ends.size(); ++i) {
        const std::string end_at = range_at + "/" + std::to_string(i);
        ends.at(i) = number(range[i], end_at);
        if (std::abs(ends.at(i)) > kMaxJointRangeDeg) {
          const std::string limit = std::to_string(static_cast<int>(kMaxJointRangeDeg));
          fail(end_at, range[i].dump() + " is outside -" + limit + " ~ " + limit +
                           " degrees (8 turns either way)");
        }
      }
      if (!(ends[0] < ends[1])) {
        fail(range_at, "low " + range[0].dump() + " must be less than high " + range[1].dump());
      }
      joint.range_deg = std::pair{ends[0], ends[1]};
    }
    return joint;
  }

  PortConfig parse_port(const json& value, const std::string& at) {
    object(value, at,
           {"name", "link", "servos", "adapter_latency_ms", "adapter_chip", "joints", "hand",
            "description"});
    PortConfig port;
    port.name = string(member(value, at, "name"), at + "/name");
    // Port names appear in logs, traces and control-API requests and replies: keep them plain.
    const bool plain = std::all_of(port.name.begin(), port.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.' || c == '-';
    });
    if (!plain || port.name.size() > kMaxPortName) {
      fail(at + "/name", "must be 1 to 32 letters, digits, '_', '.' or '-'");
    }
    if (value.contains("link")) {
      port.link = string(value["link"], at + "/link");
    }
    if (value.contains("adapter_latency_ms")) {
      port.adapter_latency_ms = static_cast<int>(integer(
          value["adapter_latency_ms"], at + "/adapter_latency_ms", 0, kMaxAdapterLatencyMs));
    }
    if (value.contains("adapter_chip")) {
      port.adapter_chip = string(value["adapter_chip"], at + "/adapter_chip");
      if (!adapter_packet_data(*port.adapter_chip)) {
        fail(at + "/adapter_chip",
             "unknown chip \"" + *port.adapter_chip + "\" (known: " + adapter_chip_names() + ")");
      }
    }
    const json& servos = member(value, at, "servos");
    if (!servos.is_array()) {
      fail(at + "/servos", "must be an array of servos");
    }
    for (std::size_t i = 0; i < servos.size(); ++i) {
      const std::string servo_at = at + "/servos/" + std::to_string(i);
      for (ServoConfig& servo : parse_servo(servos[i], servo_at)) {
        port.servos.push_back(std::move(servo));
      }
    }
    if (const auto other = other_maker_servo(port, library_)) {
      // The entry of "servos" the offending servo came from: entries with "ids" make several.
      std::size_t entry = 0;
      for (std::size_t i = 0, made = 0; i < servos.size(); ++i) {
        made += servos[i].contains("ids") ? servos[i]["ids"].size() : 1;
        if (*other < made) {
          entry = i;
          break;
        }
      }
      fail(at + "/servos/" + std::to_string(entry), other_maker_reason(port, *other, library_));
    }
    if (value.contains("joints")) {
      port.joints = parse_joints(value["joints"], at + "/joints", port);
    }
    if (value.contains("hand")) {
      port.hands = hand_starts_of_json(value["hand"], origin_, at + "/hand",
                                       std::filesystem::path(origin_).parent_path());
    }
    return port;
  }

  // One entry of "servos": a servo, or several of one model with "ids".
  std::vector<ServoConfig> parse_servo(const json& value, const std::string& at) {
    object(value, at, {"model", "id", "ids", "baud", "protocol", "items", "description"});
    const std::string name = string(member(value, at, "model"), at + "/model");
    const auto spec = library_.find(name);
    if (!spec) {
      fail(at + "/model", library_.why_not_found(name));
    }
    std::vector<std::uint8_t> ids;
    if (value.contains("id") == value.contains("ids")) {
      fail(at, "needs exactly one of \"id\" and \"ids\"");
    }
    if (value.contains("id")) {
      ids.push_back(static_cast<std::uint8_t>(integer(value["id"], at + "/id", 0, kMaxServoId)));
    } else {
      const json& list = value["ids"];
      if (!list.is_array() || list.empty()) {
        fail(at + "/ids", "must be a non-empty array of IDs");
      }
      for (std::size_t i = 0; i < list.size(); ++i) {
        ids.push_back(static_cast<std::uint8_t>(
            integer(list[i], at + "/ids/" + std::to_string(i), 0, kMaxServoId)));
      }
    }
    std::vector<std::pair<std::string, std::int64_t>> items;
    // The shorthands first, so that an explicit item override wins.
    if (value.contains("baud")) {
      const auto bps = integer(value["baud"], at + "/baud", 1, UINT32_MAX);
      try {
        items.emplace_back("baud_rate",
                           baud_rate_item_value(*spec, static_cast<std::uint32_t>(bps)));
      } catch (const std::invalid_argument& e) {
        fail(at + "/baud", e.what());
      }
    }
    if (value.contains("protocol")) {
      const auto protocol = protocol_of_json(value["protocol"]);
      if (!protocol) {
        fail(at + "/protocol", value["protocol"].dump() +
                                   " is no protocol (known: " + wire::protocol_json_list() + ")");
      }
      try {
        if (auto item = protocol_item(*spec, *protocol, library_)) {
          items.push_back(std::move(*item));
        }
      } catch (const std::invalid_argument& e) {
        fail(at + "/protocol", e.what());
      }
    }
    if (value.contains("items")) {
      const json& overrides = value["items"];
      if (!overrides.is_object()) {
        fail(at + "/items", "must be an object of item keys and values");
      }
      for (const auto& [key, v] : overrides.items()) {
        const std::string item_at = at + "/items/" + pointer_token(key);
        if (!v.is_number_integer()) {
          fail(item_at, "must be an integer");
        }
        items.emplace_back(key, v.get<std::int64_t>());
        try {
          check_servo({name, ids.front(), {items.back()}}, library_);
        } catch (const std::invalid_argument& e) {
          fail(item_at, e.what());
        }
      }
    }
    std::vector<ServoConfig> out;
    out.reserve(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      out.push_back({name, ids[i], items});
      try {
        check_servo_id(out.back(), *spec);
      } catch (const std::invalid_argument& e) {
        fail(value.contains("id") ? at + "/id" : at + "/ids/" + std::to_string(i), e.what());
      }
    }
    return out;
  }

  std::string origin_;
  const ModelLibrary& library_;
};

}  // namespace

std::string_view robot_role_name(RobotRole role) {
  return role == RobotRole::Leader ? "leader" : "follower";
}

std::optional<std::size_t> adapter_packet_data(std::string_view chip) {
  for (const AdapterChip& c : kAdapterChips) {
    if (chip == c.name) {
      return c.packet_data;
    }
  }
  return std::nullopt;
}

std::string adapter_chip_names() {
  std::string names;
  for (const AdapterChip& c : kAdapterChips) {
    names += (names.empty() ? "" : ", ") + std::string(c.name);
  }
  return names;
}

BusConfig parse_config(const std::string& text, const std::string& origin,
                       const ModelLibrary& library) {
  return ConfigParser(origin, library).parse(text);
}

json parse_json(const std::string& text, const std::string& origin) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    throw ConfigError(origin, "", std::string("not valid JSON: ") + e.what());
  }
}

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError(path.string(), "", "cannot be read");
  }
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

BusConfig read_config(const std::filesystem::path& path, const ModelLibrary& library) {
  BusConfig config = parse_config(read_text_file(path), path.string(), library);
  // The MJCF file is named relative to the config file.
  if (config.physics && config.physics->mjcf.is_relative()) {
    config.physics->mjcf = path.parent_path() / config.physics->mjcf;
  }
  return config;
}

std::int64_t baud_rate_item_value(const model::ModelSpec& spec, std::uint32_t bps) {
  std::string offered;
  for (const auto& b : spec.baud_rates) {
    if (b.bps == bps) {
      return b.index;
    }
    offered += (offered.empty() ? "" : ", ") + std::to_string(b.bps);
  }
  throw std::invalid_argument(spec.name + " cannot do " + std::to_string(bps) + " bps (it offers " +
                              offered + ")");
}

std::optional<std::pair<std::string, std::int64_t>> protocol_item(const model::ModelSpec& spec,
                                                                  wire::Protocol protocol,
                                                                  const ModelLibrary& library) {
  if (!spec.speaks(protocol)) {
    throw std::invalid_argument(spec.name + " cannot speak " +
                                std::string(wire::protocol_title(protocol)) +
                                "; the models that can: " + models_speaking(protocol, library));
  }
  for (const char* key : {"protocol_type", "protocol_version"}) {
    if (spec.find(key) != nullptr) {
      return std::pair<std::string, std::int64_t>{key, wire::traits(protocol).type_value};
    }
  }
  return std::nullopt;
}

std::string models_speaking(wire::Protocol protocol, const ModelLibrary& library) {
  // A dozen names say which kind of model it takes; the full list is one command away.
  constexpr std::size_t kListed = 12;
  ModelFilter filter;
  filter.protocol = protocol;
  const auto models = library.select(filter);
  if (models.empty()) {
    return "none in the model library";
  }
  std::string out;
  for (std::size_t i = 0; i < models.size() && i < kListed; ++i) {
    out += (out.empty() ? "" : ", ") + models[i]->name;
  }
  if (models.size() > kListed) {
    out += " and " + std::to_string(models.size() - kListed) + " more (dxlemu models --protocol " +
           std::string(wire::traits(protocol).spelling) + ")";
  }
  return out;
}

std::optional<wire::Protocol> protocol_of_json(const nlohmann::json& value) {
  // DYNAMIXEL's protocols as their numbers, the others by their spelling (as model files).
  if (value.is_string()) {
    const auto p = wire::protocol_from_spelling(value.get<std::string>());
    return p && wire::protocol_number(*p) == 0 ? p : std::nullopt;
  }
  if (value.is_number_integer()) {
    return wire::protocol_from_number(value.get<std::int64_t>());
  }
  return std::nullopt;
}

wire::Protocol configured_protocol(const ServoConfig& servo, const model::ModelSpec& spec) {
  std::optional<wire::Protocol> out;
  for (const auto& [key, value] : servo.items) {
    if (key == "protocol_type" || key == "protocol_version") {
      out = wire::protocol_from_type_value(value);
    }
  }
  return out.value_or(spec.protocols.front());
}

void check_servo_id(const ServoConfig& servo, const model::ModelSpec& spec) {
  const wire::ProtocolTraits& row = wire::traits(configured_protocol(servo, spec));
  if (servo.id < row.min_unicast_id || servo.id > row.max_unicast_id) {
    throw std::invalid_argument("servo " + servo.model + ":" + std::to_string(servo.id) +
                                " speaks " + std::string(row.title) + ", whose IDs are " +
                                std::to_string(row.min_unicast_id) + " ~ " +
                                std::to_string(row.max_unicast_id));
  }
}

std::optional<std::size_t> other_maker_servo(const PortConfig& port, const ModelLibrary& library) {
  std::optional<model::Maker> maker;
  for (std::size_t i = 0; i < port.servos.size(); ++i) {
    const auto spec = library.find(port.servos[i].model);
    if (!spec) {
      continue;
    }
    if (!maker) {
      maker = spec->maker();
    } else if (spec->maker() != *maker) {
      return i;
    }
  }
  return std::nullopt;
}

std::string other_maker_reason(const PortConfig& port, std::size_t index,
                               const ModelLibrary& library) {
  const auto spec = library.find(port.servos.at(index).model);
  std::shared_ptr<const model::ModelSpec> first;
  for (const ServoConfig& servo : port.servos) {
    if (const auto s = library.find(servo.model); s && s->maker() != spec->maker()) {
      first = s;
      break;
    }
  }
  return spec->name + " is a " + std::string(model::maker_name(spec->maker())) + " model, but " +
         first->name + " on the same port is " + std::string(model::maker_name(first->maker())) +
         ": a port speaks one maker's protocol (put them on separate ports)";
}

void check_servo(const ServoConfig& servo, const ModelLibrary& library) {
  const auto spec = library.find(servo.model);
  if (!spec) {
    throw std::invalid_argument(library.why_not_found(servo.model));
  }
  for (const auto& [key, value] : servo.items) {
    const model::ItemSpec* item = spec->find(key);
    if (item == nullptr) {
      throw std::invalid_argument(servo.model + " has no item \"" + key + "\"");
    }
    if (item->access == model::Access::ReadOnly) {
      throw std::invalid_argument(servo.model + " " + key + " is read-only");
    }
    if (!item->in_range(value)) {
      throw std::invalid_argument(servo.model + " " + key + " " + std::to_string(value) +
                                  " is outside its range " + std::to_string(item->min) + " ~ " +
                                  std::to_string(item->max));
    }
  }
}

}  // namespace dxlemu::app
