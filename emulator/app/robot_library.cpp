#include "app/robot_library.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <system_error>

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProfileExtension = ".json";

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
  if (const char* dir = std::getenv("DXLEMU_ROBOTS_DIR"); dir != nullptr && *dir != '\0') {
    return dir;
  }
  // As shipped_models_dir(): relative to the executable, so that any install prefix works.
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    fs::path installed = (exe.parent_path() / DXLEMU_BINDIR_TO_ROBOTSDIR).lexically_normal();
    if (fs::is_directory(installed, error)) {
      return installed;
    }
  }
  return DXLEMU_SOURCE_ROBOTS_DIR;
}

}  // namespace dxlemu::app
