#pragma once

#include <array>
#include <cstdint>

#include "sim/sim_time.hpp"

namespace dxlemu::bus {

/// Counts durations (how late replies went out) in logarithmic buckets, so that a daemon that
/// runs for days keeps its percentiles in a fixed few kilobytes. Each power of two is split into
/// kSubBuckets buckets: a percentile is exact to within 1/kSubBuckets (about 6 %) of its value,
/// which is all a lateness figure needs.
class LatenessHistogram {
 public:
  /// Buckets per power of two: 2^kSubBits.
  static constexpr int kSubBits = 4;
  /// Buckets per power of two.
  static constexpr int kSubBuckets = 1 << kSubBits;

  /// Counts one duration; negative ones count as zero.
  void add(sim::SimDuration d);

  /// How many durations were counted.
  std::uint64_t count() const { return count_; }
  /// The longest counted (exact); zero when none was.
  sim::SimDuration max() const { return max_; }
  /// The duration below which a share `q` (0 ~ 1) of the counted ones lie: the upper edge of its
  /// bucket, never more than max(). Zero when none was counted.
  sim::SimDuration percentile(double q) const;

 private:
  // Durations below 2^kLinearBits ns (about 1 µs) share the first bucket: finer is noise here.
  // 2^(kLinearBits + kOctaves) ns is about 73 minutes; longer ones share the last bucket.
  static constexpr int kLinearBits = 10;
  static constexpr int kOctaves = 32;
  static constexpr int kBuckets = 1 + kOctaves * kSubBuckets;

  static int bucket_of(std::int64_t ns);
  static std::int64_t upper_edge(int bucket);

  std::array<std::uint64_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0;
  sim::SimDuration max_{0};
};

}  // namespace dxlemu::bus
