#pragma once

#include "model/hand/trajectory.hpp"
#include "model/spec/model_spec.hpp"

namespace dxlemu::model {

/// How a joint's values become shaft pulses on one servo (docs/hands.md "Units"): raw values are
/// pulses as Present Position reads them at factory settings; degrees count from the middle of
/// the servo's position range (2048 on a 4096-pulse servo, 512 on an AX or XL-320, 0 on a PRO),
/// positive the way Present Position grows.
struct JointScale {
  /// Pulses at 0°: the middle of the factory position limits.
  double middle = 0;
  /// Pulses per degree of the shaft.
  double pulses_per_degree = 1;

  /// `value` in `unit` as pulses.
  double to_pulses(double value, JointUnit unit) const {
    return unit == JointUnit::Raw ? value : middle + value * pulses_per_degree;
  }
  /// `pulses` in `unit`.
  double from_pulses(double pulses, JointUnit unit) const {
    return unit == JointUnit::Raw ? pulses : (pulses - middle) / pulses_per_degree;
  }
  /// Pulses per one of `unit`.
  double pulses_per(JointUnit unit) const {
    return unit == JointUnit::Raw ? 1.0 : pulses_per_degree;
  }

  /// The scale of a servo of `spec`.
  static JointScale of(const ModelSpec& spec);
};

}  // namespace dxlemu::model
