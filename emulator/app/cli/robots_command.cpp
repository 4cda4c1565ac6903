#include "app/cli/robots_command.hpp"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <string>

#include "app/cli/libraries.hpp"

namespace dxlemu::app {
namespace {

// The servos of every port of `config`.
std::size_t servo_count(const BusConfig& config) {
  std::size_t count = 0;
  for (const auto& port : config.ports) {
    count += port.servos.size();
  }
  return count;
}

// ROLE: "leader of so101-follower", "follower of ...", a role without a pair alone, or "-".
std::string role_text(const RobotHeader& header) {
  if (!header.role) {
    return "-";
  }
  std::string text(robot_role_name(*header.role));
  if (!header.pairs_with.empty()) {
    text += " of " + header.pairs_with;
  }
  return text;
}

}  // namespace

void list_robots(const CommandLine& line) {
  const auto library = load_library(line.model_dirs);
  const auto robots = load_robots(line.robot_dirs, library);
  if (robots.profiles().empty()) {
    std::cerr << "dxlemu: no robot profile in " << shipped_robots_dir().string()
              << " or --robots\n";
    return;
  }
  std::size_t name_width = std::string("NAME").size();
  std::size_t role_width = std::string("ROLE").size();
  std::size_t title_width = std::string("TITLE").size();
  for (const auto& [name, profile] : robots.profiles()) {
    name_width = std::max(name_width, name.size());
    role_width = std::max(role_width, role_text(profile.header()).size());
    title_width = std::max(title_width, profile.header().title.size());
  }
  constexpr int kCountWidth = 7;
  // PHYSICS: the shipped physics file of that name, for run --physics (docs/physics.md).
  constexpr int kPhysicsWidth = 9;
  constexpr std::size_t kGap = 2;
  std::cout << std::left << std::setw(static_cast<int>(name_width + kGap)) << "NAME"
            << std::setw(kCountWidth) << "PORTS" << std::setw(kCountWidth) << "SERVOS"
            << std::setw(kPhysicsWidth) << "PHYSICS"
            << std::setw(static_cast<int>(role_width + kGap)) << "ROLE"
            << std::setw(static_cast<int>(title_width + kGap)) << "TITLE"
            << "SOURCE\n";
  for (const auto& [name, profile] : robots.profiles()) {
    std::cout << std::setw(static_cast<int>(name_width + kGap)) << name << std::setw(kCountWidth)
              << profile.config.ports.size() << std::setw(kCountWidth)
              << servo_count(profile.config) << std::setw(kPhysicsWidth)
              << (robots.find_physics(name) != nullptr ? "yes" : "-")
              << std::setw(static_cast<int>(role_width + kGap)) << role_text(profile.header())
              << std::setw(static_cast<int>(title_width + kGap)) << profile.header().title
              << profile.header().sources.front() << "\n";
  }
  // The command that serves both halves of each pair in one daemon (docs/robots.md).
  const auto pairs = robots.pairs();
  if (!pairs.empty()) {
    std::cout << "\nLeader and follower pairs, both served by one daemon:\n";
  }
  for (const auto& [leader, follower] : pairs) {
    std::cout << leader << " + " << follower << ": dxlemu run --robot " << leader << " --robot "
              << follower << "\n";
  }
}

}  // namespace dxlemu::app
