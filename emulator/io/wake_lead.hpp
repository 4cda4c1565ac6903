#pragma once

#include <array>
#include <chrono>
#include <cstddef>

namespace dxlemu::io {

/// Learns how late a sleeping thread's timer wakes it, so that a driver can arm its timer that
/// much before a deadline and spin only for what is left (docs/architecture.md "The real-time
/// driver"). A fixed early wake-up costs its whole length in spinning whenever the wake-up is
/// punctual; a learned one costs only the spread of the wake-ups.
///
/// The lead is a quantile of the last kWindow wake-up latenesses, clamped to [0, max_lead]:
/// below the quantile the thread spins the difference, above it the deadline is missed by the
/// difference. Until kWindow wake-ups were seen, the lead is max_lead.
class WakeLead {
 public:
  /// How many recent wake-ups the lead is learned from.
  static constexpr std::size_t kWindow = 64;

  /// `quantile` (0 ~ 1): the share of wake-ups the lead should cover; `max_lead`: the lead
  /// before anything is learned and at most after.
  WakeLead(double quantile, std::chrono::nanoseconds max_lead);

  /// Counts one wake-up that came `lateness` after the time the timer was set for.
  void add(std::chrono::nanoseconds lateness);
  /// How long before a deadline to arm the timer.
  std::chrono::nanoseconds lead() const { return lead_; }

 private:
  void learn();

  double quantile_;
  std::chrono::nanoseconds max_lead_;
  std::chrono::nanoseconds lead_;
  std::array<std::chrono::nanoseconds, kWindow> recent_{};
  std::size_t seen_ = 0;
};

}  // namespace dxlemu::io
