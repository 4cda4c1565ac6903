#include "app/config/physics_config.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

#include "app/config/bus_config.hpp"
#include "physics/mjcf_world.hpp"

namespace dxlemu::app {
namespace {

using nlohmann::json;

// A world stepped more coarsely than this is not worth coupling to servos that tick at 1 kHz.
constexpr double kMaxTimestepMs = 100;
constexpr double kDegreesPerRad = 180 / std::numbers::pi;

class PhysicsParser {
 public:
  PhysicsParser(const std::string& origin, const std::vector<PortConfig>& ports)
      : origin_(origin), ports_(ports) {}

  PhysicsConfig parse(const json& value, const std::string& at) {
    if (!physics::mujoco_available()) {
      fail(at,
           "this build of dxlemu has no MuJoCo, so it cannot simulate physics (rebuild with "
           "Debian's libmujoco-dev installed and -DDXLEMU_MUJOCO=ON, docs/physics.md)");
    }
    object(value, at, {"mjcf", "timestep_ms", "joints", "description"});
    PhysicsConfig config;
    config.origin = origin_;
    config.pointer = at;
    config.mjcf = string(member(value, at, "mjcf"), at + "/mjcf");
    if (value.contains("timestep_ms")) {
      const double dt = number(value["timestep_ms"], at + "/timestep_ms");
      if (!(dt > 0) || dt > kMaxTimestepMs) {
        fail(at + "/timestep_ms", "must be more than 0 and at most 100 ms");
      }
      config.timestep_ms = dt;
    }
    const json& joints = member(value, at, "joints");
    if (!joints.is_array() || joints.empty()) {
      fail(at + "/joints", "must be a non-empty array of joints");
    }
    std::set<std::pair<std::string, int>> servos;
    std::set<std::string> names;
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const std::string joint_at = at + "/joints/" + std::to_string(i);
      JointConfig joint = parse_joint(joints[i], joint_at);
      if (!servos.insert({joint.port, joint.id}).second) {
        fail(joint_at, "servo " + std::to_string(joint.id) + " of port " + joint.port +
                           " already drives a joint");
      }
      if (!names.insert(joint.joint).second) {
        fail(joint_at + "/joint", "joint \"" + joint.joint + "\" is already driven by a servo");
      }
      config.joints.push_back(std::move(joint));
    }
    return config;
  }

 private:
  [[noreturn]] void fail(const std::string& pointer, const std::string& reason) const {
    throw ConfigError(origin_, pointer, reason);
  }

  void object(const json& value, const std::string& at,
              std::initializer_list<const char*> allowed) const {
    if (!value.is_object()) {
      fail(at, "must be an object");
    }
    for (const auto& m : value.items()) {
      if (std::none_of(allowed.begin(), allowed.end(),
                       [&](const char* a) { return m.key() == a; })) {
        std::string list;
        for (const char* a : allowed) {
          list += (list.empty() ? "" : ", ") + std::string(a);
        }
        // Field names of our own: none needs RFC 6901 escaping, a stray one may.
        std::string token;
        for (const char c : m.key()) {
          token += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
        }
        fail(at + "/" + token, "unknown field (allowed: " + list + ")");
      }
    }
  }

  const json& member(const json& value, const std::string& at, const char* key) const {
    if (!value.contains(key)) {
      fail(at + "/" + key, "is required");
    }
    return value.at(key);
  }

  std::string string(const json& value, const std::string& at) const {
    if (!value.is_string() || value.get<std::string>().empty()) {
      fail(at, "must be a non-empty string");
    }
    return value.get<std::string>();
  }

  double number(const json& value, const std::string& at) const {
    if (!value.is_number() || !std::isfinite(value.get<double>())) {
      fail(at, "must be a number");
    }
    return value.get<double>();
  }

  JointConfig parse_joint(const json& value, const std::string& at) const {
    object(value, at,
           {"port", "id", "joint", "gear", "direction", "zero_offset_deg", "description"});
    JointConfig joint;
    joint.port = string(member(value, at, "port"), at + "/port");
    const auto port = std::find_if(ports_.begin(), ports_.end(),
                                   [&](const PortConfig& p) { return p.name == joint.port; });
    if (port == ports_.end()) {
      fail(at + "/port", "no port is called \"" + joint.port + "\"");
    }
    const json& id = member(value, at, "id");
    if (!id.is_number_integer() || id.get<std::int64_t>() < 0 ||
        id.get<std::int64_t>() > kMaxServoId) {
      fail(at + "/id", "must be a servo ID, 0 ~ 252");
    }
    joint.id = static_cast<std::uint8_t>(id.get<std::int64_t>());
    if (std::none_of(port->servos.begin(), port->servos.end(),
                     [&](const ServoConfig& s) { return s.id == joint.id; })) {
      fail(at + "/id", "port " + joint.port + " has no servo " + std::to_string(joint.id));
    }
    joint.joint = string(member(value, at, "joint"), at + "/joint");
    if (value.contains("gear")) {
      joint.gear = number(value["gear"], at + "/gear");
      if (!(joint.gear > 0)) {
        fail(at + "/gear", "must be more than 0 (shaft turns per joint turn)");
      }
    }
    if (value.contains("direction")) {
      const json& d = value["direction"];
      if (!d.is_number_integer() || (d.get<std::int64_t>() != 1 && d.get<std::int64_t>() != -1)) {
        fail(at + "/direction", "must be 1 or -1");
      }
      joint.direction = static_cast<int>(d.get<std::int64_t>());
    }
    if (value.contains("zero_offset_deg")) {
      joint.zero_offset_deg = number(value["zero_offset_deg"], at + "/zero_offset_deg");
    }
    return joint;
  }

  const std::string& origin_;
  const std::vector<PortConfig>& ports_;
};

}  // namespace

PhysicsConfig parse_physics(const json& value, const std::string& origin,
                            const std::vector<PortConfig>& ports, const std::string& pointer) {
  return PhysicsParser(origin, ports).parse(value, pointer);
}

PhysicsConfig read_physics_file(const std::filesystem::path& file,
                                const std::vector<PortConfig>& ports) {
  const std::string origin = file.string();
  PhysicsConfig config = parse_physics(parse_json(read_text_file(file), origin), origin, ports, "");
  if (config.mjcf.is_relative()) {
    config.mjcf = file.parent_path() / config.mjcf;
  }
  return config;
}

std::unique_ptr<physics::WorldClock> load_physics(const PhysicsConfig& config,
                                                  sim::SimDuration tick) {
  const double tick_ms = std::chrono::duration<double, std::milli>(tick).count();
  const double timestep_s = config.timestep_ms.value_or(tick_ms) / 1e3;
  std::unique_ptr<physics::World> world;
  try {
    world = physics::load_mjcf_world(config.mjcf, timestep_s);
  } catch (const physics::PhysicsError& e) {
    throw ConfigError(config.origin, config.pointer + "/mjcf",
                      config.mjcf.string() + ": " + e.what());
  }
  try {
    return std::make_unique<physics::WorldClock>(std::move(world), tick);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(config.origin, config.pointer + "/timestep_ms", e.what());
  }
}

model::JointMapping joint_mapping(const PhysicsConfig& config, std::size_t index,
                                  const physics::World& world) {
  const JointConfig& j = config.joints.at(index);
  const auto found = world.find_joint(j.joint);
  if (!found) {
    std::string names;
    for (const std::string& name : world.joints()) {
      names += (names.empty() ? "" : ", ") + name;
    }
    throw ConfigError(config.origin, config.pointer + "/joints/" + std::to_string(index) + "/joint",
                      config.mjcf.string() + " has no hinge or slide joint \"" + j.joint +
                          "\" (its joints: " + (names.empty() ? "none" : names) + ")");
  }
  model::JointMapping m;
  m.joint = *found;
  m.gear = j.gear;
  m.direction = j.direction;
  m.zero_offset_rad = j.zero_offset_deg / kDegreesPerRad;
  return m;
}

}  // namespace dxlemu::app
