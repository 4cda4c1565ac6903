#include "model/hand/joint_scale.hpp"

#include <cmath>
#include <optional>

#include "model/motion/motion_items.hpp"
#include "model/spec/motor_params.hpp"

namespace dxlemu::model {
namespace {

constexpr double kDegreesPerTurn = 360;

}  // namespace

JointScale JointScale::of(const ModelSpec& spec) {
  const MotorParams params = MotorParams::of(spec);
  const MotionItems items(spec);
  // The middle of the factory position limits (CW/CCW Angle Limit on Protocol 1.0 models),
  // rounded as the servos' own factory Present Position is: 2047.5 is 2048.
  std::optional<std::size_t> low = items.min_position_limit;
  std::optional<std::size_t> high = items.max_position_limit;
  if (!low || !high) {
    low = items.cw_angle_limit;
    high = items.ccw_angle_limit;
  }
  double middle = params.pulses_per_rev / 2;
  if (low && high) {
    middle =
        std::round(static_cast<double>(spec.items[*low].initial + spec.items[*high].initial) / 2);
  }
  return JointScale{middle, params.pulses_per_rev / kDegreesPerTurn};
}

}  // namespace dxlemu::model
