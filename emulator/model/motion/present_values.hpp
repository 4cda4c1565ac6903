#pragma once

#include <cstdint>

#include "model/motion/drive.hpp"
#include "model/motion/motion_context.hpp"

namespace dxlemu::model {

/// The Present values that stand for the physical world rather than for the motion: Present
/// Position, Present Temperature and Present (Input) Voltage. The model writes them; set
/// device-side (tests, the control API), they move the shaft, the winding or the supply there.
class PresentValues {
 public:
  /// Present values working on `motion`, which must outlive it.
  explicit PresentValues(MotionContext& motion) : motion_(motion) {}

  /// Writes Present (Input) Voltage and Present Temperature, and remembers what the table shows
  /// now (Present Position included: the drive has just written it).
  void publish();

  /// Moves the shaft (through `drive`'s raw_goal), the winding or the supply where Present
  /// values set device-side since publish() say. Returns true when one was set.
  bool absorb(const Drive& drive);

 private:
  MotionContext& motion_;
  // The Present values the last publish() wrote.
  std::int64_t position_ = 0;
  std::int64_t temperature_ = 0;
  std::int64_t voltage_ = 0;
};

}  // namespace dxlemu::model
