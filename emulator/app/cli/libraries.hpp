#pragma once

#include <string>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/config/robot_library.hpp"

namespace dxlemu::app {

/// The shipped model library with the --models directories `dirs` added (docs/models.md).
ModelLibrary load_library(const std::vector<std::string>& dirs);

/// The shipped robot profiles with the --robots directories `dirs` added, their servos checked
/// against `models` (docs/robots.md).
RobotLibrary load_robots(const std::vector<std::string>& dirs, const ModelLibrary& models);

/// --physics of run and check: attaches the physics file `physics` names (a path, or a shipped
/// one's name looked up with the --robots directories `robot_dirs`) to `config`; nothing when
/// `physics` is empty (docs/physics.md).
void attach_physics_option(BusConfig& config, const std::string& physics,
                           const std::vector<std::string>& robot_dirs, const ModelLibrary& library);

}  // namespace dxlemu::app
