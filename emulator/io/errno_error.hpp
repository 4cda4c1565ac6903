#pragma once

#include <cerrno>
#include <string>
#include <system_error>

namespace dxlemu::io {

/// Throws std::system_error for the current errno, `what` naming the call that failed and on
/// what ("/tmp/dxlemu-dxl0: read").
[[noreturn]] inline void throw_errno(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

}  // namespace dxlemu::io
