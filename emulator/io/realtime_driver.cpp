#include "io/realtime_driver.hpp"

#include <sys/prctl.h>

namespace dxlemu::io {
namespace {

// Linux lets a sleeping thread's timer wake-ups be late by its "timer slack" (50 µs by default),
// to batch them and save power. Replies are modelled to the ns and their timer is the only one we
// arm, so ask for the least: 1 ns (0 would mean "back to the default").
constexpr unsigned long kTimerSlackNs = 1;

}  // namespace

namespace detail {

void set_least_timer_slack() {
  // Per thread: this is the thread that runs io (the daemon has one). Best effort: a kernel that
  // refuses leaves the default, which costs precision, not correctness.
  prctl(PR_SET_TIMERSLACK, kTimerSlackNs, 0, 0, 0);
}

}  // namespace detail

template class BasicRealTimeDriver<SteadyClock>;

}  // namespace dxlemu::io
