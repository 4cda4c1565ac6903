#include "app/config/robot_library.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <system_error>

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProfileExtension = ".json";
// Beside the profiles: the physics files --physics can name (docs/physics.md "Shipped arms").
constexpr const char* kPhysicsFolder = "physics";

// Refuses the "pairs_with" of the profile in `file`.
[[noreturn]] void refuse_pair(const fs::path& file, const std::string& reason) {
  throw ConfigError(file.string(), "/robot/pairs_with", reason);
}

}  // namespace

void RobotLibrary::add_directory(const fs::path& dir, const ModelLibrary& models) {
  std::vector<fs::path> files;
  for (const auto& f : fs::directory_iterator(dir)) {
    if (f.path().extension() == kProfileExtension) {
      files.push_back(f.path());
    }
  }
  std::sort(files.begin(), files.end());  // deterministic: directory order is not
  for (const fs::path& file : files) {
    BusConfig config = read_config(file, models);
    if (!config.robot) {
      throw ConfigError(file.string(), "/robot",
                        "is required in a robot profile (docs/robots.md \"Header\")");
    }
    const std::string stem = file.stem().string();
    if (config.robot->name != stem) {
      throw ConfigError(file.string(), "/robot/name",
                        "\"" + config.robot->name + "\" must be the file's name, \"" + stem + "\"");
    }
    for (PortConfig& port : config.ports) {
      port.robot = stem;
    }
    // A user's profile replaces the shipped one of its name, as a user's model file does.
    profiles_.insert_or_assign(stem, RobotProfile{file, std::move(config)});
  }
  const fs::path physics_dir = dir / kPhysicsFolder;
  std::error_code error;
  if (fs::is_directory(physics_dir, error)) {
    for (const auto& f : fs::directory_iterator(physics_dir)) {
      if (f.path().extension() == kProfileExtension) {
        physics_.insert_or_assign(f.path().stem().string(), f.path());
      }
    }
  }
}

RobotLibrary RobotLibrary::load(const fs::path& shipped_dir,
                                const std::vector<fs::path>& extra_dirs,
                                const ModelLibrary& models) {
  RobotLibrary library;
  std::error_code error;
  if (fs::is_directory(shipped_dir, error)) {
    library.add_directory(shipped_dir, models);
  }
  for (const fs::path& dir : extra_dirs) {
    if (!fs::is_directory(dir, error)) {
      throw ConfigError(dir.string(), "", "is not a directory");
    }
    library.add_directory(dir, models);
  }
  // Only now: a user's directory may add the other half of a shipped pair, or replace it.
  library.check_pairs();
  return library;
}

void RobotLibrary::check_pairs() const {
  for (const auto& entry : profiles_) {
    const std::string& name = entry.first;
    const RobotHeader& header = entry.second.header();
    if (header.pairs_with.empty()) {
      continue;
    }
    const fs::path& file = entry.second.file;
    const RobotProfile* other = find(header.pairs_with);
    if (other == nullptr) {
      refuse_pair(file, why_not_found(header.pairs_with));
    }
    const RobotRole wanted =
        *header.role == RobotRole::Leader ? RobotRole::Follower : RobotRole::Leader;
    const RobotHeader& them = other->header();
    const std::string where = header.pairs_with + " (" + other->file.string() + ")";
    if (them.role != wanted) {
      refuse_pair(file, where + " is " +
                            (them.role ? "a " + std::string(robot_role_name(*them.role))
                                       : "neither leader nor follower") +
                            ": a " + std::string(robot_role_name(*header.role)) + " pairs with a " +
                            std::string(robot_role_name(wanted)));
    }
    if (them.pairs_with != name) {
      refuse_pair(file, where + " must name " + name + " back in its \"pairs_with\" (it names " +
                            (them.pairs_with.empty() ? std::string("none") : them.pairs_with) +
                            ")");
    }
  }
}

std::vector<std::pair<std::string, std::string>> RobotLibrary::pairs() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [name, profile] : profiles_) {
    // load() checked that each pair names itself from both sides: the leader's side lists it.
    if (profile.header().role == RobotRole::Leader && !profile.header().pairs_with.empty()) {
      out.emplace_back(name, profile.header().pairs_with);
    }
  }
  return out;
}

const RobotProfile* RobotLibrary::find(const std::string& name) const {
  const auto it = profiles_.find(name);
  return it == profiles_.end() ? nullptr : &it->second;
}

std::string RobotLibrary::why_not_found(const std::string& name) const {
  std::string known;
  for (const auto& [key, profile] : profiles_) {
    known += (known.empty() ? "" : ", ") + key;
  }
  return "unknown robot \"" + name + "\" (known: " + (known.empty() ? "none" : known) +
         "; dxlemu robots lists them)";
}

const fs::path* RobotLibrary::find_physics(const std::string& name) const {
  const auto it = physics_.find(name);
  return it == physics_.end() ? nullptr : &it->second;
}

fs::path RobotLibrary::physics_file(const std::string& argument) const {
  std::error_code error;
  if (fs::is_regular_file(argument, error)) {
    return argument;
  }
  if (argument.find('/') == std::string::npos) {
    if (const fs::path* file = find_physics(argument)) {
      return *file;
    }
  }
  std::string known;
  for (const auto& [key, file] : physics_) {
    known += (known.empty() ? "" : ", ") + key;
  }
  throw std::invalid_argument("--physics: " + argument +
                              " is no file, nor a shipped physics model (known: " +
                              (known.empty() ? "none" : known) + "; docs/physics.md)");
}

void attach_physics(BusConfig& config, const fs::path& file) {
  if (config.physics) {
    throw std::invalid_argument("--physics: the config has a \"physics\" of its own (" +
                                config.physics->origin + ")");
  }
  config.physics = read_physics_file(file, config.ports);
}

BusConfig robot_bus(const RobotLibrary& robots, const std::string& name,
                    const std::optional<fs::path>& link) {
  const RobotProfile* profile = robots.find(name);
  if (profile == nullptr) {
    throw std::invalid_argument("--robot: " + robots.why_not_found(name));
  }
  BusConfig config = profile->config;
  if (link) {
    if (config.ports.size() != 1) {
      std::string names;
      for (const PortConfig& port : config.ports) {
        names += (names.empty() ? "" : ", ") + port.name;
      }
      throw std::invalid_argument(
          "--link: robot " + name + " has " + std::to_string(config.ports.size()) + " ports (" +
          names + "); copy " + profile->file.string() + " and set each port's link there");
    }
    config.ports.front().link = *link;
  }
  return config;
}

std::string served_port_name(const std::string& robot, const std::string& port,
                             std::size_t robot_ports) {
  return robot_ports == 1 ? robot : robot + "." + port;
}

namespace {

// The names of `requests`, for messages: "a, b".
std::string request_names(const std::vector<RobotRequest>& requests) {
  std::string names;
  for (const RobotRequest& request : requests) {
    names += (names.empty() ? "" : ", ") + request.name;
  }
  return names;
}

// Port `port`'s description in messages about merged robots: "port arm of so101-leader".
std::string port_of(const PortConfig& port, const std::string& original) {
  return "port " + original + " of " + port.robot;
}

}  // namespace

BusConfig robots_bus(const RobotLibrary& robots, const std::vector<RobotRequest>& requests,
                     const std::optional<fs::path>& link) {
  if (requests.empty()) {
    throw std::invalid_argument("--robot: no robot to serve");
  }
  if (requests.size() == 1) {
    // One robot: its profile's bus as it is, port names included (state files and scripts
    // written for it keep working).
    BusConfig config = robot_bus(robots, requests.front().name, link);
    if (requests.front().physics) {
      attach_physics(config, robots.physics_file(*requests.front().physics));
    }
    return config;
  }
  if (link) {
    throw std::invalid_argument("--link: several robots are served (" + request_names(requests) +
                                "), each on the links of its profile; copy a profile to change "
                                "its links");
  }
  BusConfig merged;
  std::string physics_robot;
  // The profile's own name of each merged port, for messages.
  std::vector<std::string> original_names;
  for (std::size_t r = 0; r < requests.size(); ++r) {
    const RobotRequest& request = requests[r];
    for (std::size_t earlier = 0; earlier < r; ++earlier) {
      if (requests[earlier].name == request.name) {
        throw std::invalid_argument("--robot: " + request.name +
                                    " is given twice; one daemon serves a robot once");
      }
    }
    BusConfig one = robot_bus(robots, request.name, std::nullopt);
    // The physics file names the profile's own ports: parsed against them, then renamed.
    if (request.physics) {
      attach_physics(one, robots.physics_file(*request.physics));
    }
    std::map<std::string, std::string> renamed;
    for (PortConfig& port : one.ports) {
      const std::string name = served_port_name(request.name, port.name, one.ports.size());
      renamed[port.name] = name;
      original_names.push_back(port.name);
      port.name = name;
      port.robot = request.name;
    }
    if (one.physics) {
      if (merged.physics) {
        throw std::invalid_argument("--physics: " + physics_robot + " and " + request.name +
                                    " both have physics, and a daemon simulates one world; "
                                    "serve one of them with a second dxlemu run");
      }
      for (JointConfig& joint : one.physics->joints) {
        joint.port = renamed.at(joint.port);
      }
      merged.physics = std::move(one.physics);
      physics_robot = request.name;
    }
    for (PortConfig& port : one.ports) {
      merged.ports.push_back(std::move(port));
    }
  }
  for (std::size_t i = 0; i < merged.ports.size(); ++i) {
    const PortConfig& port = merged.ports[i];
    if (port.name.size() > kMaxPortName) {
      throw std::invalid_argument("--robot: " + port_of(port, original_names[i]) +
                                  " would be called \"" + port.name +
                                  "\", longer than a port name's " + std::to_string(kMaxPortName) +
                                  " characters; copy the profile under a shorter name");
    }
    for (std::size_t j = 0; j < i; ++j) {
      const PortConfig& other = merged.ports[j];
      if (other.name == port.name) {
        throw std::invalid_argument("--robot: " + port_of(other, original_names[j]) + " and " +
                                    port_of(port, original_names[i]) + " would both be called \"" +
                                    port.name + "\"");
      }
      if (port.link && other.link &&
          port.link->lexically_normal() == other.link->lexically_normal()) {
        throw std::invalid_argument("--robot: " + port_of(other, original_names[j]) + " and " +
                                    port_of(port, original_names[i]) + " have the same link " +
                                    port.link->string() +
                                    "; copy one profile and give its port another link");
      }
    }
  }
  return merged;
}

fs::path shipped_robots_dir() {
  return shipped_data_dir("DXLEMU_ROBOTS_DIR", DXLEMU_BINDIR_TO_ROBOTSDIR, "",
                          DXLEMU_SOURCE_ROBOTS_DIR);
}

}  // namespace dxlemu::app
