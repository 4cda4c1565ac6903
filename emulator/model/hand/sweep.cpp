#include "model/hand/sweep.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace dxlemu::model {
namespace {

/// The five positions a joint passes: start, middle, low, high, middle.
constexpr std::size_t kWaypoints = 5;

/// Whether the hand holds a joint still once it reached waypoint `index`: at low and high.
bool held_at(std::size_t index) {
  return index == 2 || index == 3;
}

std::array<double, kWaypoints> waypoints(const SweepJoint& joint) {
  return {joint.start, joint.middle, joint.low, joint.high, joint.middle};
}

/// How long `joint` takes for the move from `from` to `to`.
double move_s(const SweepJoint& joint, double from, double to) {
  return std::max(std::abs(to - from) / joint.speed_per_s, kMinSweepMoveS);
}

void check(const SweepJoint& joint) {
  const std::string name = "sweep joint " + joint.joint + ": ";
  if (!(joint.speed_per_s > 0) || !std::isfinite(joint.speed_per_s)) {
    throw std::invalid_argument(name + "the speed must be finite and more than 0");
  }
  for (const double value : waypoints(joint)) {
    if (!std::isfinite(value)) {
      throw std::invalid_argument(name + "start, low, high and middle must be finite");
    }
  }
  if (joint.low > joint.high) {
    throw std::invalid_argument(name + "low must not be above high");
  }
}

/// Keyframes under construction: a row is appended after the previous one by a move's duration.
class Keyframes {
 public:
  explicit Keyframes(std::vector<double> first) { rows_.push_back(std::move(first)); }

  /// The latest row, to be copied and changed for the next.
  const std::vector<double>& last() const { return rows_.back(); }

  void append(double after_s, std::vector<double> row) {
    times_s_.push_back(times_s_.back() + after_s);
    rows_.push_back(std::move(row));
  }

  Trajectory build(const std::vector<SweepJoint>& joints) && {
    std::vector<TrajectoryColumn> columns;
    columns.reserve(joints.size());
    for (const SweepJoint& joint : joints) {
      columns.push_back({joint.joint, joint.unit});
    }
    return {std::move(columns), std::move(times_s_), rows_, {}, "sweep"};
  }

 private:
  std::vector<double> times_s_{0};
  std::vector<std::vector<double>> rows_;
};

}  // namespace

Trajectory make_sweep(const std::vector<SweepJoint>& joints, SweepOrder order) {
  if (joints.empty()) {
    throw std::invalid_argument("a sweep needs at least one joint");
  }
  for (const SweepJoint& joint : joints) {
    check(joint);
  }
  std::vector<double> row;
  row.reserve(joints.size());
  for (const SweepJoint& joint : joints) {
    row.push_back(joint.start);
  }
  Keyframes keyframes(std::move(row));

  // The move from waypoint `from` to the next by every joint at once, lasting as long as the
  // slowest joint needs, then the hold there if there is one; OneByOne moves this way only from
  // start to middle.
  const auto all_move = [&](std::size_t from) {
    double longest = 0;
    std::vector<double> next;
    next.reserve(joints.size());
    for (const SweepJoint& joint : joints) {
      const auto points = waypoints(joint);
      longest = std::max(longest, move_s(joint, points[from], points[from + 1]));
      next.push_back(points[from + 1]);
    }
    keyframes.append(longest, next);
    if (held_at(from + 1)) {
      keyframes.append(kSweepHoldS, std::move(next));
    }
  };

  all_move(0);
  if (order == SweepOrder::Together) {
    for (std::size_t from = 1; from + 1 < kWaypoints; ++from) {
      all_move(from);
    }
  } else {
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const auto points = waypoints(joints[j]);
      for (std::size_t from = 1; from + 1 < kWaypoints; ++from) {
        std::vector<double> next = keyframes.last();
        next[j] = points[from + 1];
        keyframes.append(move_s(joints[j], points[from], points[from + 1]), next);
        if (held_at(from + 1)) {
          keyframes.append(kSweepHoldS, std::move(next));
        }
      }
    }
  }
  return std::move(keyframes).build(joints);
}

}  // namespace dxlemu::model
