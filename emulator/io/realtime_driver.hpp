#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>

#include "sim/scheduler.hpp"

namespace dxlemu::io {

/// Binds the Scheduler to the wall clock: simulated time is the steady_clock time since the
/// driver started, and one Asio timer wakes the io_context at the scheduler's next deadline
/// (absolute, so errors do not accumulate). Nothing is polled while nothing is due.
class RealTimeDriver {
 public:
  RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler);

  /// Runs every event due by now, so that the scheduler's now() is the present.
  void catch_up();

  /// Arms the timer for the scheduler's next deadline (call after scheduling anything).
  void rearm();

 private:
  sim::SimTime wall_now() const;

  sim::Scheduler& scheduler_;
  boost::asio::steady_timer timer_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dxlemu::io
