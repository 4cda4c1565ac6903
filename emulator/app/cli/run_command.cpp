#include "app/cli/run_command.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "app/cli/libraries.hpp"
#include "app/config/bus_options.hpp"
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
  // The hands' motion is not served yet: refused rather than silently ignored.
  const bool hands = !line.hands.empty() ||
                     std::any_of(line.robots.begin(), line.robots.end(),
                                 [](const RobotRequest& robot) { return !robot.hands.empty(); });
  if (hands) {
    throw std::invalid_argument("--hand: this dxlemu serves no virtual hands yet");
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
  apply_bus_options(config, library, line.baud, line.protocol);
  Emulator emulator(library, config, options);
  emulator.run(std::cout);
}

}  // namespace dxlemu::app
