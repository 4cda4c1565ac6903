#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>

#include "sim/sim_time.hpp"

namespace dxlemu::sim {

/// The virtual clock and its queue of timed events. Everything below io/ takes its time from here;
/// it never reads a real clock. Simulated time moves only when advance_to()/advance_by() is called
/// (by a test, or by io/'s RealTimeDriver). Single-threaded: no locks, no callbacks from other
/// threads. Not copyable or movable, because components hold references to it.
class Scheduler {
 public:
  /// Identifies a scheduled event. Ids start at 1 and strictly increase in scheduling order, so 0
  /// never names an event and can serve as "none" for callers.
  using EventId = std::uint64_t;

  /// The work an event does when it runs. The scheduler owns it until it runs or is cancelled.
  using Callback = std::function<void()>;

  /// Creates a scheduler whose simulated clock reads SimTime{} (the start) and has nothing pending.
  Scheduler() = default;

  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;
  Scheduler(Scheduler&&) = delete;
  Scheduler& operator=(Scheduler&&) = delete;
  ~Scheduler() = default;

  /// Current simulated time (virtual clock). While an event's callback runs, this is that event's
  /// due time; after advance_to(t) it is exactly t.
  [[nodiscard]] SimTime now() const { return now_; }

  /// Schedules `fn` (must not be empty) to run at simulated time `at`. A time earlier than now() is
  /// clamped to now(): the event runs on the next advance_to()/advance_by()/run_due(), after
  /// everything already scheduled for now(). Returns the event's id for cancel().
  EventId schedule_at(SimTime at, Callback fn);

  /// Schedules `fn` to run `delay` (simulated ns) after now(). A negative delay is clamped to zero
  /// (see schedule_at); a delay that would overflow SimTime saturates at the largest SimTime.
  EventId schedule_after(SimDuration delay, Callback fn);

  /// Cancels a pending event and destroys its callback. Returns true if the event was still
  /// pending; false if it already ran (or is running), was already cancelled, or the id is unknown.
  /// Safe to call from inside a callback, including for events due at the same time.
  bool cancel(EventId id);

  /// Simulated due time of the earliest pending (not cancelled) event, or nullopt if none.
  [[nodiscard]] std::optional<SimTime> next_deadline() const;

  /// Number of events scheduled and not yet run or cancelled.
  [[nodiscard]] std::size_t pending() const { return queue_.size(); }

  /// Runs every event due at or before `t` in order of due time, ties in scheduling order, moving
  /// now() to each event's time as it runs. Events that callbacks schedule at or before `t` run in
  /// this same call, in their proper place. Afterwards now() == t. If t < now(), runs nothing and
  /// leaves now() unchanged (time never moves backwards). Returns the number of events run. Must
  /// not be called from inside a callback.
  std::size_t advance_to(SimTime t);

  /// advance_to(now() + d). A negative `d` runs nothing; an overflowing one saturates. Returns the
  /// number of events run.
  std::size_t advance_by(SimDuration d);

  /// Runs the events due at now() (including ones they schedule for now()) without moving time.
  /// Returns the number of events run. Must not be called from inside a callback.
  std::size_t run_due();

 private:
  /// Queue order: due time first, then id, which is scheduling order.
  using Key = std::pair<SimTime, EventId>;

  /// now() + d, with d clamped to [0, the largest duration that does not overflow].
  [[nodiscard]] SimTime clamped_after(SimDuration d) const;

  std::map<Key, Callback> queue_;
  std::unordered_map<EventId, SimTime> due_by_id_;
  SimTime now_{};
  EventId next_id_ = 1;
  bool running_ = false;
};

}  // namespace dxlemu::sim
