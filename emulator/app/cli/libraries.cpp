#include "app/cli/libraries.hpp"

#include <filesystem>

#include "app/config/physics_config.hpp"

namespace dxlemu::app {

ModelLibrary load_library(const std::vector<std::string>& dirs) {
  return ModelLibrary::load(shipped_models_dir(),
                            std::vector<std::filesystem::path>(dirs.begin(), dirs.end()));
}

RobotLibrary load_robots(const std::vector<std::string>& dirs, const ModelLibrary& models) {
  return RobotLibrary::load(shipped_robots_dir(),
                            std::vector<std::filesystem::path>(dirs.begin(), dirs.end()), models);
}

void attach_physics_option(BusConfig& config, const std::string& physics,
                           const std::vector<std::string>& robot_dirs,
                           const ModelLibrary& library) {
  if (!physics.empty()) {
    const auto robots = load_robots(robot_dirs, library);
    attach_physics(config, robots.physics_file(physics));
  }
}

}  // namespace dxlemu::app
