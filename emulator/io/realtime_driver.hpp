#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <optional>
#include <utility>

#include "io/wake_lead.hpp"
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
///
/// Precision (docs/architecture.md "The real-time driver", docs/benchmarks.md): the constructor
/// sets the calling thread's Linux timer slack to 1 ns, and with Pace::WallClock the timer is
/// armed early by what the driver learned of its own wake-ups (WakeLead), the last stretch
/// being a busy-wait on steady_clock.
class RealTimeDriver {
 public:
  /// The most a timer is armed before its deadline, and the most the thread spins. Even with
  /// 1 ns of timer slack a wake-up from a sleep of 0.5 ~ 4 ms came 50 ~ 120 µs late in the median
  /// (p90 70 ~ 170 µs) on the 2-CPU virtual machine of docs/benchmarks.md; a spin ends within a
  /// clock read.
  static constexpr std::chrono::microseconds kSpinWindow{200};
  /// The share of the timer's wake-ups the early arming covers: the median. Each wake-up earlier
  /// than the lead spins the difference, each later one misses its deadline by the difference;
  /// the median keeps both to the spread of the wake-ups, a few tens of µs.
  static constexpr double kWakeQuantile = 0.5;

  /// Binds `scheduler` to a timer on `io`. Sets the timer slack of the calling thread, which must
  /// be the thread that runs `io` (threads it starts later inherit the setting).
  RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler,
                 Pace pace = Pace::WallClock);

  /// Runs every event due by now, so that the scheduler's now() is the present.
  void catch_up();

  /// Runs what is due now and arms the timer for the scheduler's next deadline (call after
  /// scheduling anything). Events already due run at once, without the timer.
  void rearm();

  /// Called after the events of each timer wake-up have run (e.g. to save what they changed).
  void set_after_events(std::function<void()> fn) { after_events_ = std::move(fn); }

  /// The steady_clock time since the driver started, as simulated time (what simulated time is
  /// under Pace::WallClock, whether or not the scheduler has caught up with it).
  sim::SimTime wall_now() const;
  /// How long before a deadline the timer is armed now.
  std::chrono::nanoseconds wake_lead() const { return lead_.lead(); }

 private:
  std::chrono::steady_clock::time_point to_steady(sim::SimTime t) const;
  void spin_to_deadline() const;
  /// Cancels the pending wait, if any.
  void disarm();
  /// Runs every event due by now, then the after-events callback.
  void run_due();

  sim::Scheduler& scheduler_;
  Pace pace_;
  std::function<void()> after_events_;
  boost::asio::steady_timer timer_;
  /// When the pending wait expires; empty when none is pending.
  std::optional<std::chrono::steady_clock::time_point> armed_;
  /// A spin-and-run handler is posted and has not run yet.
  bool spin_posted_ = false;
  WakeLead lead_{kWakeQuantile, kSpinWindow};
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dxlemu::io
