// RealTimeDriver on a clock the test moves (manual_clock.hpp), its io_context run by hand: which
// events run when, the early wake-up and the spin, manual pace. Nothing here reads a real clock.
#include "io/realtime_driver.hpp"

#include <catch2/catch.hpp>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <vector>

#include "manual_clock.hpp"
#include "sim/scheduler.hpp"

namespace {

using dxlemu::io::BasicRealTimeDriver;
using dxlemu::io::Pace;
using dxlemu::sim::Scheduler;
using dxlemu::sim::SimTime;
using dxlemu::test::ManualClock;
using dxlemu::test::ManualTime;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

using Driver = BasicRealTimeDriver<ManualClock>;
constexpr auto kWindow = Driver::kSpinWindow;

SimTime at(nanoseconds t) {
  return SimTime{t};
}

// A driver on a ManualTime, with what its events saw.
struct DriverRig {
  explicit DriverRig(Pace pace = Pace::WallClock) : driver(io, scheduler, pace, ManualClock(time)) {
    driver.set_after_events([this] { ++after_events; });
  }

  // Schedules an event at `t` that records the simulated time it ran at.
  void event_at(nanoseconds t) {
    scheduler.schedule_at(at(t), [this] { ran.push_back(scheduler.now()); });
  }
  // The clock's reading for simulated time `t` (the driver started at the clock's present).
  ManualTime::time_point clock_at(nanoseconds t) const { return start + t; }
  // Runs every handler ready now; returns how many ran.
  std::size_t poll() {
    const std::size_t n = io.poll();
    io.restart();
    return n;
  }

  ManualTime time;
  ManualTime::time_point start = time.now();
  boost::asio::io_context io;
  Scheduler scheduler;
  Driver driver;
  std::vector<SimTime> ran;
  int after_events = 0;
};

}  // namespace

TEST_CASE("A future deadline arms the timer one wake lead early, and the rest is spun",
          "[io][driver]") {
  DriverRig rig;
  rig.event_at(milliseconds(1));
  rig.driver.rearm();
  CHECK(rig.driver.wake_lead() == kWindow);  // nothing learned yet
  CHECK(rig.time.timer().expiry() == rig.clock_at(milliseconds(1) - kWindow));
  CHECK(rig.poll() == 0);

  rig.time.advance_to(rig.clock_at(milliseconds(1) - kWindow - nanoseconds(1)));
  CHECK(rig.poll() == 0);
  CHECK(rig.ran.empty());

  rig.time.advance_to(rig.clock_at(milliseconds(1) - kWindow));
  CHECK(rig.poll() == 1);
  // The event runs at its own time, to the ns, after a spin of the whole lead.
  CHECK(rig.ran == std::vector{at(milliseconds(1))});
  CHECK(rig.time.spins() == std::vector<ManualTime::duration>{kWindow});
  CHECK(rig.scheduler.now() == at(milliseconds(1)));
  CHECK(rig.after_events == 1);
  CHECK_FALSE(rig.time.timer().waiting());  // nothing left to wait for
}

TEST_CASE("An event already due runs in rearm, without the timer", "[io][driver]") {
  DriverRig rig;
  rig.time.advance_to(rig.clock_at(milliseconds(2)));
  rig.event_at(milliseconds(1));
  rig.driver.rearm();
  CHECK(rig.ran == std::vector{at(milliseconds(1))});
  // Caught up with the clock: simulated time is the clock's time since the start.
  CHECK(rig.scheduler.now() == at(milliseconds(2)));
  CHECK(rig.driver.wall_now() == at(milliseconds(2)));
  CHECK(rig.after_events == 1);
  CHECK(rig.time.timer().settings() == 0);
  CHECK(rig.time.spins().empty());
  CHECK(rig.poll() == 0);
}

TEST_CASE("catch_up runs what is due by the clock and nothing later", "[io][driver]") {
  DriverRig rig;
  rig.event_at(microseconds(500));
  rig.event_at(microseconds(501));
  rig.time.advance_to(rig.clock_at(microseconds(500)));
  rig.driver.catch_up();
  CHECK(rig.ran == std::vector{at(microseconds(500))});
  CHECK(rig.scheduler.now() == at(microseconds(500)));
  CHECK(rig.after_events == 0);  // only the driver's own wake-ups call it
}

TEST_CASE(
    "A deadline inside the wake lead is spun for in a handler of its own, after those "
    "already queued",
    "[io][driver]") {
  DriverRig rig;
  std::vector<int> order;
  boost::asio::post(rig.io, [&] { order.push_back(static_cast<int>(rig.ran.size())); });
  rig.event_at(microseconds(150));
  rig.driver.rearm();
  CHECK(rig.ran.empty());  // not spun inside rearm: other ports' bytes come first
  CHECK(rig.time.timer().settings() == 0);
  rig.driver.rearm();  // asking again posts no second spin
  CHECK(rig.poll() == 2);
  CHECK(order == std::vector{0});
  CHECK(rig.ran == std::vector{at(microseconds(150))});
  CHECK(rig.time.spins() == std::vector<ManualTime::duration>{microseconds(150)});
}

TEST_CASE("The chained events of one wake-up each get their own spin", "[io][driver]") {
  DriverRig rig;
  rig.event_at(milliseconds(1));
  rig.event_at(milliseconds(1) + microseconds(100));
  rig.driver.rearm();
  rig.time.advance_to(rig.clock_at(milliseconds(1) - kWindow));
  rig.poll();
  CHECK(rig.ran == std::vector{at(milliseconds(1)), at(milliseconds(1) + microseconds(100))});
  CHECK(rig.time.spins() == std::vector<ManualTime::duration>{kWindow, microseconds(100)});
  CHECK(rig.time.timer().settings() == 1);
  CHECK(rig.after_events == 2);
}

TEST_CASE("Re-arming for the deadline already waited for leaves the timer alone", "[io][driver]") {
  DriverRig rig;
  rig.event_at(milliseconds(1));
  rig.driver.rearm();
  rig.driver.rearm();
  CHECK(rig.time.timer().settings() == 1);
  // An earlier deadline moves the wait.
  rig.event_at(microseconds(700));
  rig.driver.rearm();
  CHECK(rig.time.timer().settings() == 2);
  CHECK(rig.time.timer().expiry() == rig.clock_at(microseconds(700) - kWindow));
  CHECK(rig.poll() == 1);  // the first wait, aborted: runs nothing
  CHECK(rig.after_events == 0);
}

TEST_CASE("With nothing left to run the timer is cancelled and its wake-up runs nothing",
          "[io][driver]") {
  DriverRig rig;
  const auto id = rig.scheduler.schedule_at(at(milliseconds(1)), [] {});
  rig.driver.rearm();
  rig.scheduler.cancel(id);
  rig.driver.rearm();
  CHECK_FALSE(rig.time.timer().waiting());
  rig.time.advance_to(rig.clock_at(milliseconds(5)));
  CHECK(rig.poll() == 1);  // the aborted wait
  CHECK(rig.after_events == 0);
  CHECK(rig.time.spins().empty());
}

TEST_CASE("A wake-up whose deadline moved away spins for nothing and waits again", "[io][driver]") {
  DriverRig rig;
  const auto id = rig.scheduler.schedule_at(at(milliseconds(1)), [] {});
  rig.driver.rearm();
  // Changed without rearm (as between the timer's expiry and its handler): the wake-up reads the
  // deadline again.
  // Just beyond the spin window of the wake-up.
  constexpr auto kMoved = milliseconds(1) + nanoseconds(1);
  rig.scheduler.cancel(id);
  rig.event_at(kMoved);
  rig.time.advance_to(rig.clock_at(milliseconds(1) - kWindow));
  CHECK(rig.poll() == 1);
  CHECK(rig.time.spins().empty());
  CHECK(rig.ran.empty());
  CHECK(rig.time.timer().expiry() == rig.clock_at(kMoved - kWindow));

  rig.time.advance_to(rig.clock_at(kMoved - kWindow));
  rig.poll();
  CHECK(rig.ran == std::vector{at(kMoved)});
  CHECK(rig.time.spins() == std::vector<ManualTime::duration>{kWindow});
}

TEST_CASE("The wake lead is learned from how late the timer's wake-ups come", "[io][driver]") {
  DriverRig rig;
  constexpr auto kLate = microseconds(30);
  nanoseconds deadline{0};
  for (std::size_t i = 0; i < dxlemu::io::WakeLead::kWindow; ++i) {
    deadline += milliseconds(1);
    rig.event_at(deadline);
    rig.driver.rearm();
    CHECK(rig.time.timer().expiry() == rig.clock_at(deadline - kWindow));
    rig.time.advance_to(rig.clock_at(deadline - kWindow + kLate));
    rig.poll();
  }
  CHECK(rig.ran.size() == dxlemu::io::WakeLead::kWindow);
  CHECK(rig.time.spins().back() == kWindow - kLate);
  REQUIRE(rig.driver.wake_lead() == kLate);

  // Armed by the learned lead now: a punctual wake-up spins only that.
  deadline += milliseconds(1);
  rig.event_at(deadline);
  rig.driver.rearm();
  CHECK(rig.time.timer().expiry() == rig.clock_at(deadline - kLate));
  rig.time.advance_to(rig.clock_at(deadline - kLate));
  rig.poll();
  CHECK(rig.time.spins().back() == kLate);

  // A wake-up later than the deadline spins nothing; the event still runs at its own time.
  deadline += milliseconds(1);
  rig.event_at(deadline);
  rig.driver.rearm();
  rig.time.advance_to(rig.clock_at(deadline + microseconds(10)));
  rig.poll();
  CHECK(rig.ran.back() == at(deadline));
  CHECK(rig.time.spins().back() == nanoseconds(0));
  CHECK(rig.scheduler.now() == at(deadline + microseconds(10)));
}

TEST_CASE("Manual pace runs only what is due at the present, at once, and never waits or spins",
          "[io][driver]") {
  DriverRig rig(Pace::Manual);
  rig.event_at(nanoseconds(0));
  rig.event_at(milliseconds(1));
  rig.driver.rearm();
  CHECK(rig.ran == std::vector{at(nanoseconds(0))});
  CHECK(rig.after_events == 1);
  CHECK(rig.time.timer().settings() == 0);

  // The clock moving does not move simulated time.
  rig.time.advance_to(rig.clock_at(milliseconds(10)));
  rig.driver.catch_up();
  rig.driver.rearm();
  CHECK(rig.poll() == 0);
  CHECK(rig.ran.size() == 1);
  CHECK(rig.scheduler.now() == at(nanoseconds(0)));
  CHECK(rig.driver.wall_now() == at(milliseconds(10)));

  // Stepped (the control API's clock.step): the event runs then; a reply it schedules for the
  // present runs in the next rearm.
  rig.scheduler.advance_to(at(milliseconds(1)));
  rig.event_at(milliseconds(1));
  rig.driver.rearm();
  CHECK(rig.ran == std::vector{at(nanoseconds(0)), at(milliseconds(1)), at(milliseconds(1))});
  CHECK(rig.time.spins().empty());
}

TEST_CASE("A wake-up already queued when the driver re-armed runs nothing", "[io][driver]") {
  DriverRig rig;
  const auto id = rig.scheduler.schedule_at(at(milliseconds(1)), [] {});
  rig.driver.rearm();
  // The timer expires; before its handler runs, another handler (bytes from the client) moves
  // the deadline and re-arms. The queued wake-up can no longer be cancelled: Asio hands it
  // success.
  rig.time.advance_to(rig.clock_at(milliseconds(1) - kWindow));
  rig.scheduler.cancel(id);
  rig.event_at(milliseconds(1) + microseconds(100));
  rig.driver.catch_up();
  rig.driver.rearm();
  CHECK(rig.time.timer().settings() == 2);
  rig.poll();
  CHECK(rig.after_events == 0);
  CHECK(rig.time.timer().settings() == 2);  // still the wait armed for the new deadline
  CHECK(rig.time.timer().waiting());

  rig.time.advance_to(rig.clock_at(milliseconds(1) + microseconds(100) - kWindow));
  rig.poll();
  CHECK(rig.ran == std::vector{at(milliseconds(1) + microseconds(100))});
  CHECK(rig.time.spins() == std::vector<ManualTime::duration>{kWindow});
  CHECK(rig.after_events == 1);
}
