#include "io/wake_lead.hpp"

#include <algorithm>
#include <cmath>

namespace dxlemu::io {
namespace {

// The lead is learned again after this many wake-ups: often enough to follow a machine whose
// load changes, seldom enough that sorting the window costs nothing per wake-up.
constexpr std::size_t kRelearnEvery = 16;

}  // namespace

WakeLead::WakeLead(double quantile, std::chrono::nanoseconds max_lead)
    : quantile_(std::clamp(quantile, 0.0, 1.0)), max_lead_(max_lead), lead_(max_lead) {}

void WakeLead::add(std::chrono::nanoseconds lateness) {
  recent_[seen_ % kWindow] = std::max(std::chrono::nanoseconds{0}, lateness);
  ++seen_;
  if (seen_ >= kWindow && seen_ % kRelearnEvery == 0) {
    learn();
  }
}

void WakeLead::learn() {
  std::array<std::chrono::nanoseconds, kWindow> sorted = recent_;
  const auto rank =
      static_cast<std::size_t>(std::lround(quantile_ * static_cast<double>(kWindow - 1)));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(rank),
                   sorted.end());
  lead_ = std::min(max_lead_, sorted[rank]);
}

}  // namespace dxlemu::io
