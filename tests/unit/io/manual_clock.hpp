#pragma once

#include <algorithm>
#include <boost/asio/error.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace dxlemu::test {

/// A clock for io::BasicRealTimeDriver that moves only when a test moves it, with timers that
/// behave as Asio's waitable timers do: a wait whose expiry the clock reaches has its handler
/// queued on the io_context with success, and from then on cancel() no longer reaches it; a wait
/// cancelled (or re-armed) before that gets operation_aborted. Handlers run only when the test
/// runs the io_context (poll(), run_one()). A spin (spin_until) moves the clock to its end at
/// once and is recorded.
///
/// The state lives in a ManualTime the test owns; ManualClock is the driver's handle on it.
class ManualTime {
 public:
  /// The clock's time point and duration (steady_clock's types, never its readings).
  using time_point = std::chrono::steady_clock::time_point;
  /// The clock's duration.
  using duration = std::chrono::steady_clock::duration;

  /// One timer of this clock.
  class Timer {
   public:
    /// A timer of `time` whose handlers run on `io`.
    Timer(boost::asio::io_context& io, ManualTime& time) : io_(&io), time_(&time) {
      time_->timers_.push_back(this);
    }
    Timer(const Timer&) = delete;
    Timer& operator=(const Timer&) = delete;
    ~Timer() {
      cancel();
      time_->forget(this);
    }

    /// The executor handlers run on.
    boost::asio::io_context::executor_type get_executor() { return io_->get_executor(); }
    /// Sets the expiry, cancelling a pending wait (as Asio's expires_at does).
    void expires_at(time_point t) {
      cancel();
      expiry_ = t;
      ++settings_;
    }
    /// Waits for the expiry; a wait on an expiry already reached completes at once (queued).
    void async_wait(std::function<void(const boost::system::error_code&)> handler) {
      waiting_.push_back(std::move(handler));
      time_->expire(*this);
    }
    /// Queues every pending wait with operation_aborted.
    void cancel() { complete(boost::asio::error::operation_aborted); }

    /// When the timer was last set to expire.
    time_point expiry() const { return expiry_; }
    /// Whether a wait is pending (not yet queued).
    bool waiting() const { return !waiting_.empty(); }
    /// How many times expires_at() was called.
    std::size_t settings() const { return settings_; }

   private:
    friend class ManualTime;
    void complete(const boost::system::error_code& ec) {
      for (auto& handler : std::exchange(waiting_, {})) {
        boost::asio::post(*io_, [handler = std::move(handler), ec] { handler(ec); });
      }
    }

    boost::asio::io_context* io_;
    ManualTime* time_;
    time_point expiry_{};
    std::vector<std::function<void(const boost::system::error_code&)>> waiting_;
    std::size_t settings_ = 0;
  };

  /// The present.
  time_point now() const { return now_; }
  /// Moves the clock to `t` (never back), queueing the handlers of the waits that expire.
  void advance_to(time_point t) {
    now_ = std::max(now_, t);
    for (Timer* timer : timers_) {
      expire(*timer);
    }
  }
  /// Moves the clock by `d`.
  void advance_by(duration d) { advance_to(now_ + d); }

  /// How long each spin_until() call spun, in order.
  const std::vector<duration>& spins() const { return spins_; }

  /// The one timer the driver made.
  Timer& timer() { return *timers_.at(0); }

 private:
  friend class ManualClock;
  void expire(Timer& timer) {
    if (timer.expiry_ <= now_) {
      timer.complete({});
    }
  }
  void forget(Timer* timer) { std::erase(timers_, timer); }
  void spin_until(time_point t) {
    spins_.push_back(t > now_ ? t - now_ : duration{0});
    advance_to(t);
  }

  // Not the epoch: a driver must work from wherever its clock stands.
  time_point now_{std::chrono::hours(1)};
  std::vector<Timer*> timers_;
  std::vector<duration> spins_;
};

/// The driver's handle on a ManualTime (the clock type of io::BasicRealTimeDriver).
class ManualClock {
 public:
  /// The clock's time point.
  using time_point = ManualTime::time_point;
  /// The clock's duration.
  using duration = ManualTime::duration;
  /// The timer make_timer() returns.
  using Timer = ManualTime::Timer;

  /// A handle on `time`, which must outlive every driver and timer using it.
  explicit ManualClock(ManualTime& time) : time_(&time) {}

  /// The present of the ManualTime.
  time_point now() const { return time_->now(); }
  /// A timer of the ManualTime whose handlers run on `io`.
  Timer make_timer(boost::asio::io_context& io) const { return Timer(io, *time_); }
  /// Moves the ManualTime to `t` and records the spin.
  void spin_until(time_point t) const { time_->spin_until(t); }

 private:
  ManualTime* time_;
};

}  // namespace dxlemu::test
