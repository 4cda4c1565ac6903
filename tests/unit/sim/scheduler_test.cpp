#include "sim/scheduler.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using dxlemu::sim::ns_since_start;
using dxlemu::sim::Scheduler;
using dxlemu::sim::sim_time_from_ns;
using dxlemu::sim::SimDuration;
using dxlemu::sim::SimTime;

}  // namespace

TEST_CASE("A new scheduler starts at time zero with nothing pending", "[sim]") {
  const Scheduler scheduler;
  CHECK(scheduler.now() == SimTime{});
  CHECK(scheduler.pending() == 0);
  CHECK_FALSE(scheduler.next_deadline().has_value());
}

TEST_CASE("Events run in time order and ties in insertion order", "[sim]") {
  Scheduler scheduler;
  std::vector<std::string> order;
  scheduler.schedule_at(sim_time_from_ns(300), [&] { order.emplace_back("c@300"); });
  scheduler.schedule_at(sim_time_from_ns(100), [&] { order.emplace_back("a@100"); });
  scheduler.schedule_at(sim_time_from_ns(200), [&] { order.emplace_back("b1@200"); });
  scheduler.schedule_at(sim_time_from_ns(200), [&] { order.emplace_back("b2@200"); });
  scheduler.schedule_at(sim_time_from_ns(100), [&] { order.emplace_back("a2@100"); });
  scheduler.schedule_at(sim_time_from_ns(200), [&] { order.emplace_back("b3@200"); });

  CHECK(scheduler.advance_to(sim_time_from_ns(1000)) == 6);
  CHECK(order ==
        std::vector<std::string>{"a@100", "a2@100", "b1@200", "b2@200", "b3@200", "c@300"});
  CHECK(scheduler.pending() == 0);
}

TEST_CASE("Event ids are distinct and grow in scheduling order", "[sim]") {
  Scheduler scheduler;
  const auto first = scheduler.schedule_at(sim_time_from_ns(50), [] {});
  const auto second = scheduler.schedule_at(sim_time_from_ns(10), [] {});
  const auto third = scheduler.schedule_after(SimDuration{5}, [] {});
  CHECK(first != 0);
  CHECK(first < second);
  CHECK(second < third);
}

TEST_CASE("During a callback now() equals the event's due time", "[sim]") {
  Scheduler scheduler;
  const std::vector<std::int64_t> due_ns{7, 1'000'003, 2'500'000'001};
  std::vector<std::int64_t> seen;
  for (const auto ns : due_ns) {
    scheduler.schedule_at(sim_time_from_ns(ns),
                          [&] { seen.push_back(ns_since_start(scheduler.now())); });
  }
  scheduler.advance_to(sim_time_from_ns(3'000'000'000));
  CHECK(seen == due_ns);
}

TEST_CASE("advance_to lands exactly on the target time", "[sim]") {
  Scheduler scheduler;

  SECTION("with nothing pending") {
    CHECK(scheduler.advance_to(sim_time_from_ns(123'456'789)) == 0);
    CHECK(ns_since_start(scheduler.now()) == 123'456'789);
  }
  SECTION("past the last event") {
    scheduler.schedule_at(sim_time_from_ns(10), [] {});
    CHECK(scheduler.advance_to(sim_time_from_ns(11)) == 1);
    CHECK(ns_since_start(scheduler.now()) == 11);
  }
  SECTION("exactly on an event, which runs") {
    bool ran = false;
    scheduler.schedule_at(sim_time_from_ns(500), [&] { ran = true; });
    CHECK(scheduler.advance_to(sim_time_from_ns(500)) == 1);
    CHECK(ran);
    CHECK(ns_since_start(scheduler.now()) == 500);
  }
  SECTION("one nanosecond before an event, which waits") {
    bool ran = false;
    scheduler.schedule_at(sim_time_from_ns(500), [&] { ran = true; });
    CHECK(scheduler.advance_to(sim_time_from_ns(499)) == 0);
    CHECK_FALSE(ran);
    CHECK(ns_since_start(scheduler.now()) == 499);
    CHECK(scheduler.advance_by(SimDuration{1}) == 1);
    CHECK(ran);
    CHECK(ns_since_start(scheduler.now()) == 500);
  }
  SECTION("advance_by adds to the current time") {
    scheduler.advance_by(SimDuration{1'000});
    scheduler.advance_by(std::chrono::microseconds{2});
    CHECK(ns_since_start(scheduler.now()) == 3'000);
  }
}

TEST_CASE("Events scheduled by callbacks inside the window run in the same advance", "[sim]") {
  Scheduler scheduler;
  std::vector<std::string> order;
  scheduler.schedule_at(sim_time_from_ns(100), [&] {
    order.emplace_back("first@100");
    // Same time as the running event: runs after it, in this advance.
    scheduler.schedule_at(scheduler.now(), [&] { order.emplace_back("same@100"); });
    // Before an event that was already queued: must run before it.
    scheduler.schedule_after(SimDuration{50}, [&] {
      order.emplace_back("nested@150");
      scheduler.schedule_after(SimDuration{10}, [&] { order.emplace_back("nested2@160"); });
    });
    // Exactly at the target: still inside the window.
    scheduler.schedule_at(sim_time_from_ns(1'000), [&] { order.emplace_back("edge@1000"); });
    // Past the target: waits for a later advance.
    scheduler.schedule_at(sim_time_from_ns(1'001), [&] { order.emplace_back("late@1001"); });
  });
  scheduler.schedule_at(sim_time_from_ns(200), [&] { order.emplace_back("queued@200"); });

  CHECK(scheduler.advance_to(sim_time_from_ns(1'000)) == 6);
  CHECK(order == std::vector<std::string>{"first@100", "same@100", "nested@150", "nested2@160",
                                          "queued@200", "edge@1000"});
  CHECK(ns_since_start(scheduler.now()) == 1'000);
  CHECK(scheduler.pending() == 1);
  CHECK(scheduler.next_deadline() == sim_time_from_ns(1'001));

  CHECK(scheduler.advance_to(sim_time_from_ns(2'000)) == 1);
  CHECK(order.back() == "late@1001");
}

TEST_CASE("Cancelling a pending event stops it from running", "[sim]") {
  Scheduler scheduler;
  bool ran = false;
  const auto id = scheduler.schedule_at(sim_time_from_ns(10), [&] { ran = true; });
  CHECK(scheduler.pending() == 1);
  CHECK(scheduler.cancel(id));
  CHECK(scheduler.pending() == 0);
  CHECK(scheduler.advance_to(sim_time_from_ns(100)) == 0);
  CHECK_FALSE(ran);
}

TEST_CASE("Cancelling an event that already ran, was cancelled or never existed returns false",
          "[sim]") {
  Scheduler scheduler;

  SECTION("already ran") {
    const auto id = scheduler.schedule_at(sim_time_from_ns(10), [] {});
    scheduler.advance_to(sim_time_from_ns(10));
    CHECK_FALSE(scheduler.cancel(id));
  }
  SECTION("cancelled twice") {
    const auto id = scheduler.schedule_at(sim_time_from_ns(10), [] {});
    CHECK(scheduler.cancel(id));
    CHECK_FALSE(scheduler.cancel(id));
  }
  SECTION("unknown id") {
    CHECK_FALSE(scheduler.cancel(0));
    CHECK_FALSE(scheduler.cancel(12'345));
  }
  SECTION("the running event cancelling itself") {
    Scheduler::EventId self = 0;
    bool cancelled_self = true;
    self = scheduler.schedule_at(sim_time_from_ns(10),
                                 [&] { cancelled_self = scheduler.cancel(self); });
    scheduler.advance_to(sim_time_from_ns(10));
    CHECK_FALSE(cancelled_self);
  }
  CHECK(scheduler.pending() == 0);
}

TEST_CASE("A callback can cancel another event due at the same time", "[sim]") {
  Scheduler scheduler;
  std::vector<std::string> order;
  Scheduler::EventId victim = 0;
  bool cancel_result = false;
  scheduler.schedule_at(sim_time_from_ns(100), [&] {
    order.emplace_back("canceller");
    cancel_result = scheduler.cancel(victim);
  });
  victim = scheduler.schedule_at(sim_time_from_ns(100), [&] { order.emplace_back("victim"); });
  scheduler.schedule_at(sim_time_from_ns(100), [&] { order.emplace_back("bystander"); });

  CHECK(scheduler.advance_to(sim_time_from_ns(100)) == 2);
  CHECK(cancel_result);
  CHECK(order == std::vector<std::string>{"canceller", "bystander"});
}

TEST_CASE("next_deadline skips cancelled events and is empty when nothing is pending", "[sim]") {
  Scheduler scheduler;
  CHECK_FALSE(scheduler.next_deadline().has_value());

  const auto early = scheduler.schedule_at(sim_time_from_ns(10), [] {});
  scheduler.schedule_at(sim_time_from_ns(20), [] {});
  const auto late = scheduler.schedule_at(sim_time_from_ns(30), [] {});
  CHECK(scheduler.next_deadline() == sim_time_from_ns(10));

  scheduler.cancel(early);
  CHECK(scheduler.next_deadline() == sim_time_from_ns(20));
  CHECK(scheduler.pending() == 2);

  scheduler.advance_to(sim_time_from_ns(25));
  CHECK(scheduler.next_deadline() == sim_time_from_ns(30));

  scheduler.cancel(late);
  CHECK_FALSE(scheduler.next_deadline().has_value());
  CHECK(scheduler.pending() == 0);
}

TEST_CASE("Times in the past are clamped to now", "[sim]") {
  Scheduler scheduler;
  scheduler.advance_to(sim_time_from_ns(1'000));
  std::vector<std::string> order;
  std::vector<std::int64_t> times;
  scheduler.schedule_at(sim_time_from_ns(1'000), [&] {
    order.emplace_back("at-now");
    times.push_back(ns_since_start(scheduler.now()));
  });
  scheduler.schedule_at(sim_time_from_ns(400), [&] {
    order.emplace_back("past");
    times.push_back(ns_since_start(scheduler.now()));
  });
  scheduler.schedule_after(SimDuration{-250}, [&] {
    order.emplace_back("negative-delay");
    times.push_back(ns_since_start(scheduler.now()));
  });
  CHECK(scheduler.next_deadline() == sim_time_from_ns(1'000));

  CHECK(scheduler.run_due() == 3);
  CHECK(order == std::vector<std::string>{"at-now", "past", "negative-delay"});
  CHECK(times == std::vector<std::int64_t>{1'000, 1'000, 1'000});
  CHECK(ns_since_start(scheduler.now()) == 1'000);
}

TEST_CASE("A delay past the end of simulated time saturates instead of overflowing", "[sim]") {
  Scheduler scheduler;
  scheduler.advance_to(sim_time_from_ns(10));
  scheduler.schedule_after(SimDuration::max(), [] {});
  CHECK(scheduler.next_deadline() == SimTime::max());
}

TEST_CASE("advance_to an earlier time runs nothing and does not move time backwards", "[sim]") {
  Scheduler scheduler;
  scheduler.advance_to(sim_time_from_ns(1'000));
  bool ran = false;
  scheduler.schedule_at(sim_time_from_ns(1'000), [&] { ran = true; });

  CHECK(scheduler.advance_to(sim_time_from_ns(999)) == 0);
  CHECK_FALSE(ran);
  CHECK(ns_since_start(scheduler.now()) == 1'000);

  CHECK(scheduler.advance_by(SimDuration{-1}) == 0);
  CHECK_FALSE(ran);
  CHECK(ns_since_start(scheduler.now()) == 1'000);
}

TEST_CASE("run_due runs only what is due now, without moving time", "[sim]") {
  Scheduler scheduler;
  scheduler.advance_to(sim_time_from_ns(50));
  std::vector<std::string> order;
  scheduler.schedule_after(SimDuration::zero(), [&] {
    order.emplace_back("due");
    scheduler.schedule_after(SimDuration::zero(), [&] { order.emplace_back("chained"); });
    scheduler.schedule_after(SimDuration{1}, [&] { order.emplace_back("later"); });
  });

  CHECK(scheduler.run_due() == 2);
  CHECK(order == std::vector<std::string>{"due", "chained"});
  CHECK(ns_since_start(scheduler.now()) == 50);
  CHECK(scheduler.pending() == 1);
  CHECK(scheduler.next_deadline() == sim_time_from_ns(51));
}
