#pragma once

namespace dxlemu::model {

/// -1, 0 or +1: the sign of `value`, 0 for 0 (sign_of() in motion_context.hpp gives +1 there).
inline double signum(double value) {
  if (value > 0) {
    return 1;
  }
  return value < 0 ? -1 : 0;
}

}  // namespace dxlemu::model
