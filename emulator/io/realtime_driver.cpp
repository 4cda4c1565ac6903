#include "io/realtime_driver.hpp"

#include <sys/prctl.h>

#include <boost/asio/post.hpp>

namespace dxlemu::io {
namespace {

// Linux lets a sleeping thread's timer wake-ups be late by its "timer slack" (50 µs by default),
// to batch them and save power. Replies are modelled to the ns and their timer is the only one we
// arm, so ask for the least: 1 ns (0 would mean "back to the default").
constexpr unsigned long kTimerSlackNs = 1;

}  // namespace

RealTimeDriver::RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler, Pace pace)
    : scheduler_(scheduler), pace_(pace), timer_(io), start_(std::chrono::steady_clock::now()) {
  // Per thread: this is the thread that runs io (the daemon has one). Best effort: a kernel that
  // refuses leaves the default, which costs precision, not correctness.
  prctl(PR_SET_TIMERSLACK, kTimerSlackNs, 0, 0, 0);
}

sim::SimTime RealTimeDriver::wall_now() const {
  return sim::SimTime{
      std::chrono::duration_cast<sim::SimDuration>(std::chrono::steady_clock::now() - start_)};
}

std::chrono::steady_clock::time_point RealTimeDriver::to_steady(sim::SimTime t) const {
  return start_ +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(t.time_since_epoch());
}

void RealTimeDriver::catch_up() {
  scheduler_.advance_to(pace_ == Pace::WallClock ? wall_now() : scheduler_.now());
}

void RealTimeDriver::rearm() {
  for (;;) {
    const auto deadline = scheduler_.next_deadline();
    if (!deadline || (pace_ == Pace::Manual && *deadline > scheduler_.now())) {
      disarm();  // in manual time a future event waits for the clock to be stepped
      return;
    }
    // Due already (every reply under `fast` and `manual` timing, or a deadline that passed while
    // the thread was busy): run it now. Going through the timer would cost a timerfd_settime
    // and an epoll round per event, the largest cost of a round trip under `fast` timing.
    if (pace_ == Pace::Manual || to_steady(*deadline) <= std::chrono::steady_clock::now()) {
      disarm();
      run_due();
      continue;
    }
    // Wall-clock time: wake as early as the timer is usually late, and spin the rest.
    const auto expiry = to_steady(*deadline) - lead_.lead();
    if (armed_ && *armed_ == expiry) {
      return;  // already waiting for this deadline
    }
    if (expiry <= std::chrono::steady_clock::now()) {
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
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) {
        return;  // re-armed or shut down
      }
      lead_.add(std::chrono::steady_clock::now() - *armed_);
      armed_.reset();
      spin_to_deadline();
      run_due();
      rearm();
    });
    return;
  }
}

void RealTimeDriver::disarm() {
  if (armed_) {
    timer_.cancel();
    armed_.reset();
  }
}

void RealTimeDriver::run_due() {
  catch_up();
  if (after_events_) {
    after_events_();
  }
}

void RealTimeDriver::spin_to_deadline() const {
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
  const auto due = to_steady(*deadline);
  if (due - std::chrono::steady_clock::now() > kSpinWindow) {
    return;
  }
  while (std::chrono::steady_clock::now() < due) {
    // Busy-wait: at most kSpinWindow, and only with an event due.
  }
}

}  // namespace dxlemu::io
