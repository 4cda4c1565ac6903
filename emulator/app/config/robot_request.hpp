#pragma once

#include <optional>
#include <string>
#include <vector>

namespace dxlemu::app {

/// One `--robot NAME` of `dxlemu run`, with the options that belong to that robot: those given
/// after it on the command line, before the next --robot (docs/robots.md "Several robots in one
/// daemon").
struct RobotRequest {
  std::string name;  ///< the robot profile's name
  /// --physics for this robot: a physics file, or the name of one beside the profiles; absent:
  /// none.
  std::optional<std::string> physics;
  /// --hand for this robot, each value as given, in command-line order.
  std::vector<std::string> hands;
  bool operator==(const RobotRequest&) const = default;
};

}  // namespace dxlemu::app
