#include "app/config/robot_library.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <system_error>

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProfileExtension = ".json";
// Beside the profiles: the physics files --physics can name (docs/physics.md "Shipped arms").
constexpr const char* kPhysicsFolder = "physics";

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
  return library;
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

fs::path shipped_robots_dir() {
  return shipped_data_dir("DXLEMU_ROBOTS_DIR", DXLEMU_BINDIR_TO_ROBOTSDIR, "",
                          DXLEMU_SOURCE_ROBOTS_DIR);
}

}  // namespace dxlemu::app
