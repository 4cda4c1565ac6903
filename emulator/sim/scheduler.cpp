#include "sim/scheduler.hpp"

#include <cassert>

namespace dxlemu::sim {

namespace {

// Clears the "inside advance_to" flag however the loop ends, so a callback that throws (a bug the
// caller reports) does not leave the scheduler refusing every later advance.
class RunningFlag {
 public:
  explicit RunningFlag(bool& flag) : flag_(flag) { flag_ = true; }
  RunningFlag(const RunningFlag&) = delete;
  RunningFlag& operator=(const RunningFlag&) = delete;
  ~RunningFlag() { flag_ = false; }

 private:
  bool& flag_;
};

}  // namespace

// Why a std::map keyed by (time, id) rather than a binary heap: the map gives an exact total order
// (time, then scheduling order, because ids only grow) with no tie-breaking subtleties, and
// cancel() can erase the event outright, so the queue never holds tombstones and next_deadline()
// and pending() are simply begin() and size(). Bus traffic keeps at most a few hundred events
// pending, so the O(log n) node allocation per event costs nothing that matters. due_by_id_ finds
// an event's key from its id for cancel().

Scheduler::EventId Scheduler::schedule_at(SimTime at, Callback fn) {
  assert(fn && "Scheduler: an event needs a callback");
  // Clamped rather than refused: a component that computes a deadline already passed (for example
  // a reply whose modelled end lies before the bytes were read) should act as soon as possible.
  const SimTime due = at < now_ ? now_ : at;
  const EventId id = next_id_++;
  queue_.emplace(Key{due, id}, std::move(fn));
  due_by_id_.emplace(id, due);
  return id;
}

Scheduler::EventId Scheduler::schedule_after(SimDuration delay, Callback fn) {
  return schedule_at(clamped_after(delay), std::move(fn));
}

bool Scheduler::cancel(EventId id) {
  const auto found = due_by_id_.find(id);
  if (found == due_by_id_.end()) {
    return false;
  }
  queue_.erase(Key{found->second, id});
  due_by_id_.erase(found);
  return true;
}

std::optional<SimTime> Scheduler::next_deadline() const {
  if (queue_.empty()) {
    return std::nullopt;
  }
  return queue_.begin()->first.first;
}

std::size_t Scheduler::advance_to(SimTime t) {
  // A nested advance would move now() past events the outer loop has still to run.
  assert(!running_ && "Scheduler: advance_to/run_due called from inside a callback");
  if (t < now_) {
    return 0;
  }
  const RunningFlag running(running_);
  std::size_t ran = 0;
  // Re-read begin() every time: a callback may schedule an earlier event than the next one we
  // knew of (but never earlier than now(), thanks to clamping), or cancel the next one.
  while (!queue_.empty() && queue_.begin()->first.first <= t) {
    // Take the event out before running it, so that the callback sees a consistent queue and a
    // cancel() of its own id returns false (it is no longer pending).
    auto node = queue_.extract(queue_.begin());
    due_by_id_.erase(node.key().second);
    now_ = node.key().first;
    node.mapped()();
    ++ran;
  }
  now_ = t;
  return ran;
}

std::size_t Scheduler::advance_by(SimDuration d) {
  if (d < SimDuration::zero()) {
    return 0;
  }
  return advance_to(clamped_after(d));
}

std::size_t Scheduler::run_due() {
  return advance_to(now_);
}

SimTime Scheduler::clamped_after(SimDuration d) const {
  if (d < SimDuration::zero()) {
    return now_;
  }
  // Saturate instead of overflowing the signed nanosecond count (undefined behaviour).
  const SimDuration headroom = SimTime::max() - now_;
  return d > headroom ? SimTime::max() : now_ + d;
}

}  // namespace dxlemu::sim
