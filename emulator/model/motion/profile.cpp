#include "model/motion/profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/motion/signum.hpp"

namespace dxlemu::model {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A limit as the planner uses it: 0, negative or NaN mean "no limit", as 0 does in Profile
/// Velocity(112) and Profile Acceleration(108) (control_table_profile_velocity.md).
double limit(double value) {
  if (value > 0) {
    return value;
  }
  return kInfinity;
}

}  // namespace

Profile::Profile(double start, double start_velocity, double goal, ProfileType type)
    : start_(start), start_velocity_(start_velocity), goal_(goal), type_(type) {}

Profile Profile::hold(double position) {
  return Profile(position, 0, position, ProfileType::None);
}

Profile Profile::velocity_based(double start, double start_velocity, double goal,
                                double max_velocity, double acceleration) {
  const double velocity = std::isfinite(start_velocity) ? start_velocity : 0;
  const double vmax = limit(max_velocity);
  const double accel = limit(acceleration);
  const double distance = goal - start;

  if (std::isinf(accel)) {
    if (std::isinf(vmax)) {
      // Profile Velocity 0: "Profile not used (Step Instruction)"; the goal is the desired
      // position at once.
      Profile step(start, velocity, goal, ProfileType::None);
      step.finish();
      return step;
    }
    if (distance == 0) {
      return hold(goal);
    }
    // Profile Acceleration 0 = infinite acceleration: the velocity jumps to the profile velocity
    // toward the goal whatever it was (velocity override has nothing to keep continuous).
    Profile profile(start, velocity, goal, ProfileType::Rectangular);
    const double cruise_velocity = signum(distance) * vmax;
    profile.push(std::abs(distance) / vmax, 0, cruise_velocity);
    profile.finish();
    return profile;
  }

  if (distance == 0 && velocity == 0) {
    return hold(goal);
  }
  Profile profile(start, velocity, goal, ProfileType::Triangular);
  // Velocity override (control_table_profile_velocity.md): the trajectory starts from the present
  // velocity. When it points away from the goal, or is too fast to stop before the goal, first
  // brake to rest, then plan from there (coming back after an overshoot).
  const double stopping_distance = velocity * velocity / (2 * accel);
  const bool away = velocity * distance < 0 || distance == 0;
  if (velocity != 0 && (away || stopping_distance > std::abs(distance))) {
    profile.brake(accel);
  }
  profile.approach(vmax, accel);
  profile.finish();
  return profile;
}

Profile Profile::time_based(double start, double start_velocity, double goal, double total_ms,
                            double accel_ms) {
  if (!(total_ms > 0) || std::isinf(total_ms)) {
    // Profile Velocity 0 stands for an infinite velocity (control_table_profile_velocity.md).
    return velocity_based(start, start_velocity, goal, kInfinity, kInfinity);
  }
  // "Profile Acceleration(108) will not exceed 50% of Profile Velocity(112) value."
  const double t1 = accel_ms > 0 ? std::min(accel_ms, total_ms / 2) : 0;
  const double distance = goal - start;
  const double length = std::abs(distance);
  const double velocity = std::isfinite(start_velocity) ? start_velocity : 0;

  if (velocity != 0) {
    // Not stated by the e-Manual: with a start velocity the time span cannot be met exactly, so
    // use the limits of the same move from rest, velocity-based. With nothing to travel the
    // present speed stands for the peak, braked within the acceleration time.
    const double peak = length > 0 ? length / (total_ms - t1) : std::abs(velocity);
    const double accel = t1 > 0 ? peak / t1 : kInfinity;
    return velocity_based(start, velocity, goal, peak, accel);
  }
  if (length == 0) {
    return hold(goal);
  }

  // From rest: t1 of acceleration, t3 - 2·t1 at the peak, t1 of deceleration, so the distance is
  // peak · (t3 - t1).
  const double direction = signum(distance);
  const double peak = length / (total_ms - t1);
  if (t1 == 0) {
    Profile profile(start, 0, goal, ProfileType::Rectangular);
    profile.push(total_ms, 0, direction * peak);
    profile.finish();
    return profile;
  }
  // At the 50% cap there is no time at the peak: the Moving Status note calls that triangular.
  const bool triangular = 2 * t1 >= total_ms;
  Profile profile(start, 0, goal, triangular ? ProfileType::Triangular : ProfileType::Trapezoidal);
  const double accel = direction * peak / t1;
  profile.push(t1, accel, direction * peak);
  profile.push(total_ms - 2 * t1, 0, direction * peak);
  profile.push(t1, -accel, 0);
  profile.finish();
  return profile;
}

ProfilePoint Profile::at(double t_ms) const {
  if (t_ms < 0) {
    return ProfilePoint{start_, start_velocity_};
  }
  if (!(t_ms < duration_ms_)) {
    return ProfilePoint{goal_, 0};
  }
  for (const Segment& segment : segments_) {
    if (t_ms < segment.start_ms + segment.duration_ms) {
      return segment.at(std::max(0.0, t_ms - segment.start_ms));
    }
  }
  return ProfilePoint{goal_, 0};
}

ProfilePoint Profile::Segment::at(double tau_ms) const {
  // A segment that slows down is evaluated from its end and one that speeds up (or cruises) from
  // its start: every rounded operation is then monotonic in time, so the sampled position never
  // steps back in a plain move, and the final deceleration ends exactly on the goal.
  double p = 0;
  double v = 0;
  if (acceleration * velocity < 0) {
    const double r = duration_ms - tau_ms;
    p = end_position - end_velocity * r + 0.5 * acceleration * r * r;
    v = end_velocity - acceleration * r;
  } else {
    p = position + velocity * tau_ms + 0.5 * acceleration * tau_ms * tau_ms;
    v = velocity + acceleration * tau_ms;
  }
  // The velocity keeps its sign inside a segment, so the position stays between the ends.
  p = std::clamp(p, std::min(position, end_position), std::max(position, end_position));
  return ProfilePoint{p, v};
}

ProfilePoint Profile::end_state() const {
  if (segments_.empty()) {
    return ProfilePoint{start_, start_velocity_};
  }
  return ProfilePoint{segments_.back().end_position, segments_.back().end_velocity};
}

void Profile::push(double duration_ms, double acceleration, double end_velocity) {
  if (!(duration_ms > 0)) {
    return;
  }
  const ProfilePoint from = end_state();
  const double start_ms =
      segments_.empty() ? 0 : segments_.back().start_ms + segments_.back().duration_ms;
  // After a velocity jump (rectangular) the segment starts at its cruise velocity.
  const double velocity = acceleration == 0 ? end_velocity : from.velocity;
  const double end_position =
      from.position + velocity * duration_ms + 0.5 * acceleration * duration_ms * duration_ms;
  segments_.push_back(Segment{start_ms, duration_ms, from.position, velocity, acceleration,
                              end_position, end_velocity});
}

void Profile::brake(double acceleration) {
  const double velocity = end_state().velocity;
  push(std::abs(velocity) / acceleration, -signum(velocity) * acceleration, 0);
}

void Profile::approach(double max_velocity, double acceleration) {
  const ProfilePoint from = end_state();
  const double distance = goal_ - from.position;
  if (distance == 0 && from.velocity == 0) {
    return;
  }
  const double direction = distance != 0 ? signum(distance) : signum(from.velocity);
  const double length = std::abs(distance);
  const double speed = direction * from.velocity;  // >= 0: toward the goal
  const double accel = direction * acceleration;

  if (speed > max_velocity) {
    // A start velocity above the profile velocity is first brought down to it.
    type_ = ProfileType::Trapezoidal;
    push((speed - max_velocity) / acceleration, -accel, direction * max_velocity);
  } else {
    // Accelerating from `speed` to a peak v and braking to rest covers
    // (v² - speed²)/(2a) + v²/(2a), so the peak that exactly fills the distance is
    // sqrt(a·ΔPos + speed²/2). From rest this is the e-Manual's triangle: t1 >= t2.
    const double peak_squared = acceleration * length + speed * speed / 2;
    if (!(peak_squared > max_velocity * max_velocity)) {
      type_ = ProfileType::Triangular;
      const double peak = std::max(speed, std::sqrt(peak_squared));
      push((peak - speed) / acceleration, accel, direction * peak);
      push(peak / acceleration, -accel, 0);
      return;
    }
    type_ = ProfileType::Trapezoidal;
    push((max_velocity - speed) / acceleration, accel, direction * max_velocity);
  }
  // Cruise at the profile velocity until the braking distance v²/(2a) is left.
  const double left = std::abs(goal_ - end_state().position);
  const double braking = max_velocity * max_velocity / (2 * acceleration);
  push((left - braking) / max_velocity, 0, direction * max_velocity);
  push(max_velocity / acceleration, -accel, 0);
}

void Profile::finish() {
  if (segments_.empty()) {
    duration_ms_ = 0;
    return;
  }
  Segment& last = segments_.back();
  last.end_position = goal_;
  last.end_velocity = 0;
  duration_ms_ = last.start_ms + last.duration_ms;
}

}  // namespace dxlemu::model
