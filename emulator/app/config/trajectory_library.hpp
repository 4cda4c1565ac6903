#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace dxlemu::app {

/// The folder of shipped trajectories beside the robot profiles (docs/hands.md "Shipped
/// trajectories"): robots/trajectories/.
inline constexpr const char* kTrajectoryFolder = "trajectories";

/// The trajectory file a hand plays for `argument` (--hand, hand.play's "file"): `argument`
/// itself when it is a file; else, for a name without '/', NAME.csv or NAME.jsonl of the first
/// of `dirs` that has one (the shipped folder, then each --robots DIR's). Throws
/// std::invalid_argument naming the trajectories there are.
std::filesystem::path find_trajectory(const std::string& argument,
                                      const std::vector<std::filesystem::path>& dirs);

}  // namespace dxlemu::app
