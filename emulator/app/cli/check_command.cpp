#include "app/cli/check_command.hpp"

#include <chrono>
#include <iostream>
#include <stdexcept>

#include "app/cli/libraries.hpp"
#include "app/config/physics_config.hpp"

namespace dxlemu::app {

void check_config(const CommandLine& line) {
  const auto library = load_library(line.model_dirs);
  BusConfig config;
  std::string checked;
  if (!line.check_robot.empty()) {
    const auto robots = load_robots(line.robot_dirs, library);
    config = robot_bus(robots, line.check_robot, std::nullopt);
    checked = line.check_robot + " (" + robots.find(line.check_robot)->file.string() + ")";
  } else if (!line.check_file.empty()) {
    config = read_config(line.check_file, library);
    checked = line.check_file;
  } else {
    throw std::invalid_argument("check: give a config FILE or --robot NAME");
  }
  attach_physics_option(config, line.physics, line.robot_dirs, library);
  // The MJCF loads and names every joint (at the default motion tick: `run --tick-hz` may
  // still refuse a timestep that does not divide its own).
  if (config.physics) {
    const auto world = load_physics(*config.physics, std::chrono::milliseconds(1));
    for (std::size_t i = 0; i < config.physics->joints.size(); ++i) {
      joint_mapping(*config.physics, i, world->world());
    }
  }
  std::cout << checked << ": ok\n";
  for (const auto& port : config.ports) {
    std::cout << "  " << port.name << ": " << port.servos.size()
              << (port.servos.size() == 1 ? " servo" : " servos");
    if (port.link) {
      std::cout << " at " << port.link->string();
    }
    std::cout << "\n";
  }
  if (config.physics) {
    std::cout << "  physics: " << config.physics->mjcf.string() << ", "
              << config.physics->joints.size()
              << (config.physics->joints.size() == 1 ? " joint" : " joints") << "\n";
  }
}

}  // namespace dxlemu::app
