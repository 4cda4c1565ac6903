#include "bus/late_reply_guard.hpp"

#include <cstdio>

namespace dxlemu::bus {
namespace {

std::string ms(sim::SimDuration d) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%.1f ms", static_cast<double>(d.count()) / 1e6);
  return text.data();
}

}  // namespace

LateReplyGuard::LateReplyGuard(ByteLink& next, Clock now, LateReplyPolicy policy, Warn warn)
    : next_(next), now_(std::move(now)), policy_(policy), warn_(std::move(warn)) {}

bool LateReplyGuard::deliver(std::span<const std::uint8_t> bytes, sim::SimTime at,
                             std::uint32_t bps) {
  const sim::SimTime now = now_();
  const sim::SimDuration lateness = std::max(sim::SimDuration{0}, now - at);
  histogram_.add(lateness);
  for (std::size_t i = 0; i < over_.size(); ++i) {
    over_[i] += lateness > LatenessSummary::kThresholds[i] ? 1 : 0;
  }
  const bool drop = policy_.drop_after > sim::SimDuration{0} && lateness > policy_.drop_after;
  if (lateness > policy_.warn_after) {
    note_late(lateness, drop, now);
  }
  if (drop) {
    ++dropped_;
    return true;
  }
  return next_.deliver(bytes, at, bps);
}

void LateReplyGuard::note_late(sim::SimDuration lateness, bool dropped, sim::SimTime now) {
  ++unreported_late_;
  unreported_dropped_ += dropped ? 1 : 0;
  unreported_max_ = std::max(unreported_max_, lateness);
  if (last_warning_ && now - *last_warning_ < policy_.warn_interval) {
    return;
  }
  std::string message =
      std::to_string(unreported_late_) + (unreported_late_ == 1 ? " reply" : " replies") +
      " went out more than " + ms(policy_.warn_after) + " later than a servo would send " +
      (unreported_late_ == 1 ? "it" : "them") + " (at most " + ms(unreported_max_) + " late";
  if (policy_.drop_after > sim::SimDuration{0}) {
    message += "; " + std::to_string(unreported_dropped_) + " later than " +
               ms(policy_.drop_after) + " dropped instead";
  }
  message +=
      "): dxlemu did not get a CPU in time, the machine is overloaded (see docs/timing.md "
      "\"Late replies\"; --realtime-priority helps)";
  if (warn_) {
    warn_(message);
  }
  last_warning_ = now;
  unreported_late_ = 0;
  unreported_dropped_ = 0;
  unreported_max_ = sim::SimDuration{0};
}

LatenessSummary LateReplyGuard::summary() const {
  LatenessSummary s;
  s.deliveries = histogram_.count();
  s.dropped = dropped_;
  s.over = over_;
  s.p50 = histogram_.percentile(0.5);
  s.p99 = histogram_.percentile(0.99);
  s.max = histogram_.max();
  s.drop_after = policy_.drop_after;
  return s;
}

}  // namespace dxlemu::bus
