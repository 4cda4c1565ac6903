#include "model/motion/drive.hpp"

namespace dxlemu::model {

std::unique_ptr<Drive> Drive::of(MotionContext& motion) {
  switch (motion.traits.drive) {
    case DriveKind::JointWheel:
      return joint_wheel_drive(motion);
    case DriveKind::OperatingMode:
      return operating_mode_drive(motion);
  }
  return operating_mode_drive(motion);
}

}  // namespace dxlemu::model
