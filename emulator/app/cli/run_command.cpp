#include "app/cli/run_command.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "app/cli/libraries.hpp"
#include "app/config/bus_options.hpp"
#include "app/config/hand_start.hpp"
#include "app/config/robot_library.hpp"
#include "app/config/trajectory_library.hpp"
#include "app/config/web_address.hpp"
#include "app/daemon/emulator.hpp"
#include "app/daemon/log.hpp"

namespace dxlemu::app {
namespace {

// The one bus of --servo and --link: port dxl0.
PortConfig port_of_options(const CommandLine& line) {
  PortConfig port;
  port.name = "dxl0";
  port.link = std::filesystem::path(line.link);
  std::vector<std::string> servo_options = line.servo_options;
  if (servo_options.empty()) {
    servo_options.emplace_back(kDefaultServos);
  }
  for (const std::string& option : servo_options) {
    for (auto& servo : parse_servo_option(option)) {
      port.servos.push_back(std::move(servo));
    }
  }
  return port;
}

// Puts each --hand on its port: the port of the --robot it follows, or the only port.
void attach_hand_options(BusConfig& config, const CommandLine& line) {
  const auto attach = [&config](const std::string& robot, const std::string& spec) {
    std::vector<PortConfig*> ports;
    for (PortConfig& port : config.ports) {
      if (robot.empty() || port.robot == robot) {
        ports.push_back(&port);
      }
    }
    if (ports.size() != 1) {
      const std::string whose = robot.empty() ? "the config" : "robot " + robot;
      throw std::invalid_argument("--hand " + spec + ": " + whose + " has " +
                                  std::to_string(ports.size()) +
                                  " ports: give each port its \"hand\" in a config "
                                  "(docs/hands.md)");
    }
    ports.front()->hands.push_back(hand_start_of_option(spec));
  };
  for (const RobotRequest& robot : line.robots) {
    for (const std::string& spec : robot.hands) {
      attach(robot.name, spec);
    }
  }
  for (const std::string& spec : line.hands) {
    attach("", spec);
  }
}

}  // namespace

void serve(const CommandLine& line, bool link_given) {
  set_log_level(*parse_log_level(line.log_level));
  RunOptions options = line.options;
  options.timing = timing_mode(line.timing);
  options.tick = std::chrono::nanoseconds(std::chrono::seconds(1)) / line.tick_hz;
  options.late_reply_limit = std::chrono::milliseconds(line.late_reply_limit_ms);
  if (line.handover_us) {
    options.pty_handover = std::chrono::microseconds(*line.handover_us);
  }
  options.trajectory_dirs.push_back(shipped_robots_dir() / kTrajectoryFolder);
  if (!line.web.empty()) {
    options.web = parse_web_address(line.web);
    options.web_root = shipped_web_dir();
  }
  for (const std::string& dir : line.robot_dirs) {
    options.trajectory_dirs.push_back(std::filesystem::path(dir) / kTrajectoryFolder);
  }
  const auto library = load_library(line.model_dirs);
  BusConfig config;
  if (!line.config_file.empty()) {
    config = read_config(line.config_file, library);
  } else if (!line.robots.empty()) {
    // Each robot's --physics is attached in robots_bus, against that robot's own ports.
    const auto robots = load_robots(line.robot_dirs, library);
    config =
        robots_bus(robots, line.robots,
                   link_given ? std::optional<std::filesystem::path>(line.link) : std::nullopt);
  } else {
    config.ports.push_back(port_of_options(line));
  }
  attach_physics_option(config, line.physics, line.robot_dirs, library);
  attach_hand_options(config, line);
  apply_bus_options(config, library, line.baud,
                    line.protocol ? wire::protocol_from_spelling(*line.protocol) : std::nullopt);
  Emulator emulator(library, config, options);
  emulator.run(std::cout);
}

}  // namespace dxlemu::app
