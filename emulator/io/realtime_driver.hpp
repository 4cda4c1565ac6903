#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>

#include "sim/scheduler.hpp"

namespace dxlemu::io {

/// What moves simulated time in the daemon (docs/timing.md).
enum class Pace {
  /// Simulated time is the steady_clock time since the driver started (timing modes `realtime`
  /// and `fast`).
  WallClock,
  /// Simulated time stands still; only events due at the present run (timing mode `manual`,
  /// where the control API steps the clock).
  Manual,
};

/// Binds the Scheduler to the wall clock: simulated time is the steady_clock time since the
/// driver started, and one Asio timer wakes the io_context at the scheduler's next deadline
/// (absolute, so errors do not accumulate). Nothing is polled while nothing is due.
class RealTimeDriver {
 public:
  RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler,
                 Pace pace = Pace::WallClock);

  /// Runs every event due by now, so that the scheduler's now() is the present.
  void catch_up();

  /// Arms the timer for the scheduler's next deadline (call after scheduling anything).
  void rearm();

 private:
  sim::SimTime wall_now() const;

  sim::Scheduler& scheduler_;
  Pace pace_;
  boost::asio::steady_timer timer_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dxlemu::io
