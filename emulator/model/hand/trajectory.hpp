#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dxlemu::model {

/// The unit a trajectory column's values are in.
enum class JointUnit {
  /// Degrees of the shaft from the middle of the servo's position range (+ in the direction
  /// Present Position grows).
  Degrees,
  /// Encoder pulses as Present Position reads them at factory settings.
  Raw
};

/// One joint column of a trajectory.
struct TrajectoryColumn {
  /// The joint as written: a joint name (`shoulder_pan`) or a servo ID in decimal (`3`). Which
  /// servo it means is decided by whoever plays the trajectory.
  std::string joint;
  JointUnit unit = JointUnit::Degrees;
  bool operator==(const TrajectoryColumn&) const = default;
};

/// How a trajectory is sampled between its keyframes.
enum class Interpolation {
  /// Piecewise linear: constant speed between keyframes.
  Linear,
  /// Monotone piecewise cubic Hermite (Fritsch-Carlson, as PCHIP): passes every keyframe, never
  /// leaves the span of two neighbouring keyframes' values, continuous in value and rate.
  Cubic
};

/// Keyframes per joint, sampled by interpolation: the one form every hand (trajectory file,
/// sweep, direct move) takes. Immutable once built; pure arithmetic, no clock: times are seconds
/// of trajectory time, which starts at 0 even when the first keyframe is later (the first
/// keyframe's values hold before it).
class Trajectory {
 public:
  /// A value and its time derivative.
  struct Sample {
    double value = 0;       ///< in the column's unit
    double rate_per_s = 0;  ///< column units per second of trajectory time
  };

  /// The latest keyframe time, seconds (31 years): times then convert to the virtual clock's
  /// nanoseconds without overflow.
  static constexpr double kMaxTimeS = 1e9;
  /// The least time between two keyframes, seconds. With kMaxMagnitude it bounds every slope, so
  /// sampling never overflows.
  static constexpr double kMinStepS = 1e-6;
  /// The largest magnitude of a value, in any unit (a 4-byte position item holds less).
  static constexpr double kMaxMagnitude = 1e12;

  /// Keyframes: `times_s[r]` is row r's time in seconds (0 <= first, each at least kMinStepS
  /// after the previous, last <= kMaxTimeS), `rows[r][c]` its value of column c (finite, magnitude
  /// at most kMaxMagnitude). `lines[r]` is the line of the file that row r came from (empty: all
  /// 0, built in code); `origin` the file name or a description ("sweep"). At least one row and
  /// one column; column joints non-empty and distinct. Throws std::invalid_argument naming the
  /// first violation. `columns_line` is the line that named the columns (a CSV header, the first
  /// JSON object; 0 when built in code). The cubic's slopes are computed here.
  Trajectory(std::vector<TrajectoryColumn> columns, std::vector<double> times_s,
             const std::vector<std::vector<double>>& rows, std::vector<std::size_t> lines = {},
             std::string origin = {}, std::size_t columns_line = 0);

  /// The joint columns, in the order written.
  const std::vector<TrajectoryColumn>& columns() const { return columns_; }
  /// The column whose joint is written exactly `joint`, or nullopt.
  std::optional<std::size_t> find_column(std::string_view joint) const;
  /// Keyframe times, seconds, strictly increasing.
  const std::vector<double>& times_s() const { return times_s_; }
  /// The number of keyframes (rows), at least 1.
  std::size_t row_count() const { return times_s_.size(); }
  /// Row `row` (< row_count())'s value of `column`, in the column's unit.
  double value(std::size_t row, std::size_t column) const {
    return values_[column * row_count() + row];
  }
  /// Every row's value of `column`, in row order (for range checks).
  std::span<const double> column_values(std::size_t column) const {
    return {values_.data() + column * row_count(), row_count()};
  }
  /// The file line row `row` (< row_count()) came from; 0 when the row was built in code.
  std::size_t line(std::size_t row) const { return lines_[row]; }
  /// The file line that named the columns (for a refusal of a column); 0 when built in code.
  std::size_t columns_line() const { return columns_line_; }
  /// The file name, or a description of what built it.
  const std::string& origin() const { return origin_; }
  /// The last keyframe's time, seconds: the trajectory runs from 0 to here.
  double duration_s() const { return times_s_.back(); }

  /// `column` (< columns().size()) at `t_s` seconds of trajectory time. Up to the first keyframe
  /// and from the last on (NaN counts as before): that keyframe's value at rate 0. At any other
  /// keyframe, the value is exactly the keyframe's and, for Linear, the rate is the segment's that
  /// starts there. One row: constant. Cubic's rate is 0 at the first and last keyframes, so a
  /// hand starts from rest and comes to rest, and the rate is continuous also where it holds.
  Sample at(std::size_t column, double t_s, Interpolation interpolation) const;

 private:
  std::vector<TrajectoryColumn> columns_;
  std::vector<double> times_s_;
  /// values_[column * row_count() + row]: a column's keyframes are contiguous for sampling.
  std::vector<double> values_;
  /// The cubic's slope (units per second) at each keyframe, laid out as values_.
  std::vector<double> slopes_;
  std::vector<std::size_t> lines_;
  std::string origin_;
  std::size_t columns_line_ = 0;
};

}  // namespace dxlemu::model
