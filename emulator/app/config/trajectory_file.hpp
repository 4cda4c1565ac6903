#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "model/hand/trajectory.hpp"

namespace dxlemu::app {

/// The two forms of a trajectory file (docs/hands.md "File formats").
enum class TrajectoryFormat {
  /// A header `time,JOINT[:deg|:raw],...` and one row of numbers per keyframe.
  Csv,
  /// One JSON object per keyframe: `{"time": 0.5, "shoulder_pan": 10, "gripper:raw": 2048}`.
  JsonLines
};

/// The most keyframes a trajectory file may hold.
inline constexpr std::size_t kMaxTrajectoryRows = 1'000'000;
/// The most joint columns a trajectory file may hold.
inline constexpr std::size_t kMaxTrajectoryColumns = 256;
/// The most values (keyframes times joint columns) a trajectory file may hold: with the two limits
/// above, what keeps a hostile file from taking more than a few hundred MB.
inline constexpr std::size_t kMaxTrajectoryValues = 16'000'000;
/// The largest trajectory file read_trajectory_file() reads, bytes.
inline constexpr std::uintmax_t kMaxTrajectoryFileBytes = 256ULL << 20;

/// The format of file `path` with contents `text`: `.csv` is Csv, `.jsonl` and `.ndjson` are
/// JsonLines (either case); otherwise JsonLines when the first line that is neither blank nor a
/// comment starts with `{`, else Csv.
TrajectoryFormat trajectory_format(const std::filesystem::path& path, const std::string& text);

/// Parses the trajectory `text` of file `origin` in `format`. Throws ConfigError (what() reads
/// "ORIGIN: line N: REASON", or "ORIGIN: end of file: REASON" when there is no header or first
/// object) for anything malformed: it never fails otherwise, whatever the text. Rows keep their
/// line numbers (1-based, blank and comment lines counted) for later checks.
model::Trajectory parse_trajectory(const std::string& text, const std::string& origin,
                                   TrajectoryFormat format);

/// Reads the trajectory file `path` (format by trajectory_format()); the trajectory's origin is
/// `path` as given. Throws ConfigError also when the file cannot be read or is larger than
/// kMaxTrajectoryFileBytes.
model::Trajectory read_trajectory_file(const std::filesystem::path& path);

}  // namespace dxlemu::app
