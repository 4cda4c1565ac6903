#include "model/hand/playback.hpp"

#include <cmath>
#include <stdexcept>

namespace dxlemu::model {
namespace {

/// Trajectory time before looping or clamping; NaN (an invalid playback) counts as 0.
double unwrapped_time(const Playback& playback, double elapsed_s) {
  const double elapsed = elapsed_s > 0 ? elapsed_s : 0;
  const double t = playback.start_s + elapsed * playback.speed;
  return std::isnan(t) ? 0 : t;
}

}  // namespace

void check_playback(const Playback& playback) {
  if (!(playback.start_s >= 0) || !std::isfinite(playback.start_s)) {
    throw std::invalid_argument("a playback's start must be a finite time of at least 0 s");
  }
  if (!(playback.speed > 0) || !std::isfinite(playback.speed)) {
    throw std::invalid_argument("a playback's speed must be finite and more than 0");
  }
}

double trajectory_time(const Trajectory& trajectory, const Playback& playback, double elapsed_s) {
  const double duration = trajectory.duration_s();
  const double t = unwrapped_time(playback, elapsed_s);
  if (playback.loop) {
    if (!(duration > 0) || !std::isfinite(t)) {
      return 0;
    }
    // fmod is exact, so a pass ends precisely at a multiple of the duration.
    const double wrapped = std::fmod(t, duration);
    return wrapped < 0 ? wrapped + duration : wrapped;
  }
  if (!(t > 0)) {
    return 0;
  }
  return t < duration ? t : duration;
}

bool ended(const Trajectory& trajectory, const Playback& playback, double elapsed_s) {
  return !playback.loop && unwrapped_time(playback, elapsed_s) >= trajectory.duration_s();
}

Trajectory::Sample play(const Trajectory& trajectory, const Playback& playback, std::size_t column,
                        double elapsed_s) {
  Trajectory::Sample sample = trajectory.at(
      column, trajectory_time(trajectory, playback, elapsed_s), playback.interpolation);
  // Trajectory seconds pass `speed` times as fast as simulated ones.
  sample.rate_per_s =
      ended(trajectory, playback, elapsed_s) ? 0 : sample.rate_per_s * playback.speed;
  return sample;
}

}  // namespace dxlemu::model
