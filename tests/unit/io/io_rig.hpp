#pragma once

#include <poll.h>
#include <stdlib.h>

#include <boost/asio/io_context.hpp>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <string>
#include <system_error>

#include "temp_dir.hpp"

// What the tests of io/ share: a temporary directory, and running an io_context by hand until
// something happened. The kernel moves PTY bytes on a worker of its own, so a test waits for
// readiness rather than for time; the timeouts only end a broken test instead of hanging it.
namespace dxlemu::test {

/// How long a test waits for the kernel at most before it fails (never reached when it passes).
inline constexpr std::chrono::seconds kKernelTimeout{10};

/// A temporary directory for the sockets and links of a test.
class IoTempDir : public TempDir {
 public:
  IoTempDir() : TempDir("dxlemu-io") {}
};

/// Runs `io`'s handlers one at a time, waiting for the next when none is ready, until `done()`
/// holds; false if kKernelTimeout passed without a handler to run.
template <typename Done>
bool run_until(boost::asio::io_context& io, Done done) {
  while (!done()) {
    io.restart();
    if (io.run_one_for(kKernelTimeout) == 0) {
      return false;
    }
  }
  return true;
}

/// Runs every handler of `io` that is ready, and those they make ready, without waiting.
inline void settle(boost::asio::io_context& io) {
  do {
    io.restart();
  } while (io.poll() > 0);
}

/// Whether `fd` has bytes to read within kKernelTimeout.
inline bool readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, static_cast<int>(std::chrono::milliseconds(kKernelTimeout).count())) > 0;
}

}  // namespace dxlemu::test
