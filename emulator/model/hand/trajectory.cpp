#include "model/hand/trajectory.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <charconv>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

namespace dxlemu::model {
namespace {

/// `value` in the shortest form that reads back the same ("0.001", "1e+09").
std::string number(double value) {
  std::array<char, 32> digits{};
  const auto end = std::to_chars(digits.begin(), digits.end(), value).ptr;
  return {digits.begin(), end};
}

/// "row 3: " for messages about one row.
std::string row_prefix(std::size_t row) {
  return "row " + std::to_string(row) + ": ";
}

/// The monotone cubic's slope at an inner keyframe from the secant slopes of the segments before
/// (`before`, `h_before` seconds long) and after it. Fritsch and Carlson's rule in the form
/// Fritsch-Butland / Brodlie give it (as SciPy's PchipInterpolator): 0 where the data turns or
/// is flat, so a keyframe at a peak is the peak; else a weighted harmonic mean of the two
/// secants, which is at most 3 times the smaller, the bound under which each Hermite segment
/// stays monotone and so never leaves the span of its two keyframes.
double inner_slope(double before, double h_before, double after, double h_after) {
  if (before * after <= 0) {
    return 0;
  }
  const double w_before = 2 * h_after + h_before;
  const double w_after = h_after + 2 * h_before;
  return (w_before + w_after) / (w_before / before + w_after / after);
}

}  // namespace

Trajectory::Trajectory(std::vector<TrajectoryColumn> columns, std::vector<double> times_s,
                       const std::vector<std::vector<double>>& rows, std::vector<std::size_t> lines,
                       std::string origin, std::size_t columns_line)
    : columns_(std::move(columns)),
      times_s_(std::move(times_s)),
      lines_(std::move(lines)),
      origin_(std::move(origin)),
      columns_line_(columns_line) {
  if (columns_.empty()) {
    throw std::invalid_argument("a trajectory needs at least one column");
  }
  std::set<std::string_view> joints;
  for (const TrajectoryColumn& column : columns_) {
    if (column.joint.empty()) {
      throw std::invalid_argument("a trajectory column needs a joint");
    }
    if (!joints.insert(column.joint).second) {
      throw std::invalid_argument("joint " + column.joint + " has two columns");
    }
  }
  const std::size_t n = times_s_.size();
  if (n == 0) {
    throw std::invalid_argument("a trajectory needs at least one row");
  }
  if (rows.size() != n) {
    throw std::invalid_argument("a trajectory has " + std::to_string(n) + " times and " +
                                std::to_string(rows.size()) + " rows");
  }
  if (lines_.empty()) {
    lines_.assign(n, 0);
  } else if (lines_.size() != n) {
    throw std::invalid_argument("a trajectory has " + std::to_string(n) + " rows and " +
                                std::to_string(lines_.size()) + " line numbers");
  }
  // Written as negations so that NaN fails each check.
  if (!(times_s_.front() >= 0)) {
    throw std::invalid_argument("the first keyframe's time must be at least 0 s");
  }
  for (std::size_t r = 1; r < n; ++r) {
    if (!(times_s_[r] - times_s_[r - 1] >= kMinStepS)) {
      throw std::invalid_argument(row_prefix(r) + "its time must come at least " +
                                  number(kMinStepS) + " s after the previous row's");
    }
  }
  if (!(times_s_.back() <= kMaxTimeS)) {
    throw std::invalid_argument("a keyframe's time must be at most " + number(kMaxTimeS) + " s");
  }

  const std::size_t width = columns_.size();
  values_.resize(width * n);
  for (std::size_t r = 0; r < n; ++r) {
    if (rows[r].size() != width) {
      throw std::invalid_argument(row_prefix(r) + "has " + std::to_string(rows[r].size()) +
                                  " values for " + std::to_string(width) + " columns");
    }
    for (std::size_t c = 0; c < width; ++c) {
      if (!(std::abs(rows[r][c]) <= kMaxMagnitude)) {
        throw std::invalid_argument(row_prefix(r) + "a value must be finite and at most " +
                                    number(kMaxMagnitude) + " in magnitude");
      }
      values_[c * n + r] = rows[r][c];
    }
  }

  // The first and last slopes are 0, not SciPy's one-sided estimates: the hand starts from rest
  // and comes to rest, so the rate stays continuous where the trajectory begins and ends to hold.
  slopes_.assign(width * n, 0);
  for (std::size_t c = 0; c < width; ++c) {
    const double* y = values_.data() + c * n;
    double* d = slopes_.data() + c * n;
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const double h_before = times_s_[k] - times_s_[k - 1];
      const double h_after = times_s_[k + 1] - times_s_[k];
      d[k] =
          inner_slope((y[k] - y[k - 1]) / h_before, h_before, (y[k + 1] - y[k]) / h_after, h_after);
    }
  }
}

std::optional<std::size_t> Trajectory::find_column(std::string_view joint) const {
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (columns_[c].joint == joint) {
      return c;
    }
  }
  return std::nullopt;
}

Trajectory::Sample Trajectory::at(std::size_t column, double t_s,
                                  Interpolation interpolation) const {
  assert(column < columns_.size() && "Trajectory::at: no such column");
  const std::size_t n = row_count();
  const double* y = values_.data() + column * n;
  // Before the first keyframe (or NaN) and from the last on, the hand holds.
  if (!(t_s > times_s_.front())) {
    return {y[0], 0};
  }
  if (t_s >= times_s_.back()) {
    return {y[n - 1], 0};
  }
  // The segment [k, k + 1] holding t_s: k is the last keyframe at or before it.
  const auto after = std::upper_bound(times_s_.begin(), times_s_.end(), t_s);
  const auto k = static_cast<std::size_t>(after - times_s_.begin()) - 1;
  const double h = times_s_[k + 1] - times_s_[k];
  const double s = (t_s - times_s_[k]) / h;
  const double y0 = y[k];
  const double y1 = y[k + 1];
  // Rounding must not carry a sample past either keyframe: that is the promise of both forms.
  const auto within = [&](double v) { return std::clamp(v, std::min(y0, y1), std::max(y0, y1)); };

  if (interpolation == Interpolation::Linear) {
    return {within(y0 + s * (y1 - y0)), (y1 - y0) / h};
  }
  // Cubic Hermite basis on s in [0, 1); slopes are per second, so they scale by h in the value
  // and the value's derivative in s scales by 1 / h in the rate.
  const double* d = slopes_.data() + column * n;
  const double s2 = s * s;
  const double s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1;
  const double h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2;
  const double h11 = s3 - s2;
  const double value = h00 * y0 + h10 * h * d[k] + h01 * y1 + h11 * h * d[k + 1];
  const double dh00 = 6 * s2 - 6 * s;
  const double dh10 = 3 * s2 - 4 * s + 1;
  const double dh11 = 3 * s2 - 2 * s;
  const double rate = dh00 * (y0 - y1) / h + dh10 * d[k] + dh11 * d[k + 1];
  return {within(value), rate};
}

}  // namespace dxlemu::model
