#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
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

/// The daemon's clock for BasicRealTimeDriver: std::chrono::steady_clock, an Asio steady_timer,
/// and a busy-wait. A driver's clock type provides these members (the unit tests have one they
/// move by hand, tests/unit/io/manual_clock.hpp):
/// - `time_point`, `duration`: a std::chrono time point and duration;
/// - `now()`: the present;
/// - `make_timer(io)`: a timer with `expires_at(time_point)`, `async_wait(handler)` and
///   `cancel()`, behaving as Asio's waitable timers do (a handler always runs once, through the
///   io_context, with operation_aborted when cancelled before it expired);
/// - `spin_until(t)`: returns at `t` (or at once if `t` has passed) without leaving the thread.
/// Empty and with static members only, so that the driver costs what it did when it named
/// steady_clock itself.
struct SteadyClock {
  /// The clock's time point.
  using time_point = std::chrono::steady_clock::time_point;
  /// The clock's duration.
  using duration = std::chrono::steady_clock::duration;
  /// The timer make_timer() returns.
  using Timer = boost::asio::steady_timer;

  /// steady_clock::now().
  static time_point now() { return std::chrono::steady_clock::now(); }
  /// A steady_timer on `io`.
  static Timer make_timer(boost::asio::io_context& io) { return Timer(io); }
  /// Busy-waits on steady_clock until `t`.
  static void spin_until(time_point t) {
    while (now() < t) {
      // Busy-wait: the driver asks for at most kSpinWindow, and only with an event due.
    }
  }
};

/// Binds the Scheduler to a clock (the daemon's: SteadyClock, as RealTimeDriver): simulated time
/// is the clock's time since the driver started, and one timer wakes the io_context at the
/// scheduler's next deadline (absolute, so errors do not accumulate). Nothing is polled while
/// nothing is due.
///
/// Precision (docs/architecture.md "The real-time driver", docs/benchmarks.md): the constructor
/// sets the calling thread's Linux timer slack to 1 ns, and with Pace::WallClock the timer is
/// armed early by what the driver learned of its own wake-ups (WakeLead), the last stretch
/// being a busy-wait on the clock (Clock::spin_until).
///
/// `Clock` is a template parameter rather than an interface so that the daemon's driver reads
/// steady_clock directly, as before, while the unit tests drive one on a clock they move by hand.
template <typename Clock>
class BasicRealTimeDriver {
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

  /// Binds `scheduler` to a timer on `io`, simulated time starting at `clock`'s present. Sets the
  /// timer slack of the calling thread, which must be the thread that runs `io` (threads it
  /// starts later inherit the setting).
  BasicRealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler,
                      Pace pace = Pace::WallClock, Clock clock = Clock{});

  /// Runs every event due by now, so that the scheduler's now() is the present.
  void catch_up();

  /// Runs what is due now and arms the timer for the scheduler's next deadline (call after
  /// scheduling anything). Events already due run at once, without the timer.
  void rearm();

  /// Called after the events of each timer wake-up have run (e.g. to save what they changed).
  void set_after_events(std::function<void()> fn) { after_events_ = std::move(fn); }

  /// The clock's time since the driver started, as simulated time (what simulated time is under
  /// Pace::WallClock, whether or not the scheduler has caught up with it).
  sim::SimTime wall_now() const;
  /// How long before a deadline the timer is armed now.
  std::chrono::nanoseconds wake_lead() const { return lead_.lead(); }

 private:
  using time_point = typename Clock::time_point;

  time_point to_clock(sim::SimTime t) const;
  void spin_to_deadline();
  /// Cancels the pending wait, if any.
  void disarm();
  /// Runs every event due by now, then the after-events callback.
  void run_due();

  sim::Scheduler& scheduler_;
  Pace pace_;
  [[no_unique_address]] Clock clock_;
  std::function<void()> after_events_;
  typename Clock::Timer timer_;
  /// When the pending wait expires; empty when none is pending.
  std::optional<time_point> armed_;
  /// A spin-and-run handler is posted and has not run yet.
  bool spin_posted_ = false;
  WakeLead lead_{kWakeQuantile, kSpinWindow};
  time_point start_;
};

/// The daemon's driver: simulated time on steady_clock.
using RealTimeDriver = BasicRealTimeDriver<SteadyClock>;

namespace detail {
/// Sets the calling thread's Linux timer slack to the least there is (realtime_driver.cpp).
void set_least_timer_slack();
}  // namespace detail

template <typename Clock>
BasicRealTimeDriver<Clock>::BasicRealTimeDriver(boost::asio::io_context& io,
                                                sim::Scheduler& scheduler, Pace pace, Clock clock)
    : scheduler_(scheduler),
      pace_(pace),
      clock_(std::move(clock)),
      timer_(clock_.make_timer(io)),
      start_(clock_.now()) {
  detail::set_least_timer_slack();
}

template <typename Clock>
sim::SimTime BasicRealTimeDriver<Clock>::wall_now() const {
  return sim::SimTime{std::chrono::duration_cast<sim::SimDuration>(clock_.now() - start_)};
}

template <typename Clock>
auto BasicRealTimeDriver<Clock>::to_clock(sim::SimTime t) const -> time_point {
  return start_ + std::chrono::duration_cast<typename Clock::duration>(t.time_since_epoch());
}

template <typename Clock>
void BasicRealTimeDriver<Clock>::catch_up() {
  scheduler_.advance_to(pace_ == Pace::WallClock ? wall_now() : scheduler_.now());
}

template <typename Clock>
void BasicRealTimeDriver<Clock>::rearm() {
  for (;;) {
    const auto deadline = scheduler_.next_deadline();
    if (!deadline || (pace_ == Pace::Manual && *deadline > scheduler_.now())) {
      disarm();  // in manual time a future event waits for the clock to be stepped
      return;
    }
    // Due already (every reply under `fast` and `manual` timing, or a deadline that passed while
    // the thread was busy): run it now. Going through the timer would cost a timerfd_settime
    // and an epoll round per event, the largest cost of a round trip under `fast` timing.
    if (pace_ == Pace::Manual || to_clock(*deadline) <= clock_.now()) {
      disarm();
      run_due();
      continue;
    }
    // Wall-clock time: wake as early as the timer is usually late, and spin the rest.
    const time_point expiry = to_clock(*deadline) - lead_.lead();
    if (armed_ && *armed_ == expiry) {
      return;  // already waiting for this deadline
    }
    if (expiry <= clock_.now()) {
      // Inside the spin window already (the next reply of a chain): programming the timer to
      // fire at once would cost a timerfd_settime for nothing. Other handlers (bytes on other
      // ports) still run before the spin.
      disarm();
      if (!spin_posted_) {
        spin_posted_ = true;
        boost::asio::post(timer_.get_executor(), [this] {
          spin_posted_ = false;
          spin_to_deadline();
          run_due();
          rearm();
        });
      }
      return;
    }
    armed_ = expiry;
    timer_.expires_at(expiry);
    timer_.async_wait([this, expiry](const boost::system::error_code& ec) {
      // A wake-up that is no longer the pending wait is stale: its timer had expired, its
      // handler queued beyond cancelling, when another handler disarmed or re-armed (Asio then
      // reports success, not operation_aborted). What it was for is handled elsewhere now.
      if (ec || armed_ != expiry) {
        return;  // re-armed, disarmed or shut down
      }
      lead_.add(clock_.now() - expiry);
      armed_.reset();
      spin_to_deadline();
      run_due();
      rearm();
    });
    return;
  }
}

template <typename Clock>
void BasicRealTimeDriver<Clock>::disarm() {
  if (armed_) {
    timer_.cancel();
    armed_.reset();
  }
}

template <typename Clock>
void BasicRealTimeDriver<Clock>::run_due() {
  catch_up();
  if (after_events_) {
    after_events_();
  }
}

template <typename Clock>
void BasicRealTimeDriver<Clock>::spin_to_deadline() {
  if (pace_ != Pace::WallClock) {
    return;
  }
  // The deadline is read again rather than remembered: a wake-up that was already queued when an
  // event was cancelled or added must not spin for a deadline that is gone. Only a deadline at
  // most kSpinWindow away is waited for here; a later one gets the timer again (rearm).
  const auto deadline = scheduler_.next_deadline();
  if (!deadline) {
    return;
  }
  const time_point due = to_clock(*deadline);
  if (due - clock_.now() > kSpinWindow) {
    return;
  }
  clock_.spin_until(due);
}

// Compiled once, in realtime_driver.cpp: the daemon's files include this header without
// instantiating the driver again.
extern template class BasicRealTimeDriver<SteadyClock>;

}  // namespace dxlemu::io
