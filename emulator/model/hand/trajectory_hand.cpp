#include "model/hand/trajectory_hand.hpp"

#include <chrono>
#include <utility>

namespace dxlemu::model {
namespace {

constexpr double kMillisecondsPerSecond = 1e3;

}  // namespace

TrajectoryHand::TrajectoryHand(std::shared_ptr<const Trajectory> trajectory, std::size_t column,
                               const Playback& playback, sim::SimTime start,
                               const JointScale& scale, double force_limit_nm, HandSource source)
    : trajectory_(std::move(trajectory)),
      column_(column),
      playback_(playback),
      start_(start),
      scale_(scale),
      force_limit_nm_(force_limit_nm),
      source_(source) {}

double TrajectoryHand::elapsed_s(sim::SimTime t) const {
  return std::chrono::duration<double>(t - start_).count();
}

std::optional<Grip> TrajectoryHand::grip(sim::SimTime t) const {
  const JointUnit unit = trajectory_->columns()[column_].unit;
  const Trajectory::Sample sample = play(*trajectory_, playback_, column_, elapsed_s(t));
  return Grip{scale_.to_pulses(sample.value, unit),
              sample.rate_per_s * scale_.pulses_per(unit) / kMillisecondsPerSecond,
              force_limit_nm_};
}

bool TrajectoryHand::still_from(sim::SimTime t) const {
  // One keyframe holds from the start; otherwise only an ended play holds still.
  return trajectory_->row_count() == 1 || ended(t);
}

double TrajectoryHand::value_at(sim::SimTime t) const {
  return play(*trajectory_, playback_, column_, elapsed_s(t)).value;
}

bool TrajectoryHand::ended(sim::SimTime t) const {
  return model::ended(*trajectory_, playback_, elapsed_s(t));
}

}  // namespace dxlemu::model
