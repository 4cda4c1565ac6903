#include "bus/lateness_histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace dxlemu::bus {

int LatenessHistogram::bucket_of(std::int64_t ns) {
  if (ns < (std::int64_t{1} << kLinearBits)) {
    return 0;
  }
  const auto u = static_cast<std::uint64_t>(ns);
  const int octave = static_cast<int>(std::bit_width(u)) - 1 - kLinearBits;  // 0: [1024, 2048) ns
  if (octave >= kOctaves) {
    return kBuckets - 1;
  }
  // The kSubBuckets bits below the leading one say where in the octave `ns` lies.
  const int shift = octave + kLinearBits - kSubBits;
  const auto sub = static_cast<int>((u >> shift) & (kSubBuckets - 1));
  return 1 + octave * kSubBuckets + sub;
}

std::int64_t LatenessHistogram::upper_edge(int bucket) {
  if (bucket == 0) {
    return (std::int64_t{1} << kLinearBits) - 1;
  }
  const int octave = (bucket - 1) / kSubBuckets;
  const int sub = (bucket - 1) % kSubBuckets;
  const std::int64_t base = std::int64_t{1} << (octave + kLinearBits);
  return base + (base / kSubBuckets) * (sub + 1) - 1;
}

void LatenessHistogram::add(sim::SimDuration d) {
  const std::int64_t ns = std::max<std::int64_t>(0, d.count());
  ++buckets_[static_cast<std::size_t>(bucket_of(ns))];
  ++count_;
  max_ = std::max(max_, sim::SimDuration{ns});
}

sim::SimDuration LatenessHistogram::percentile(double q) const {
  if (count_ == 0) {
    return sim::SimDuration{0};
  }
  // The rank of the percentile, 1-based: the smallest bucket holding at least that many.
  const auto rank = std::max<std::uint64_t>(
      1,
      static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += buckets_[static_cast<std::size_t>(b)];
    if (seen >= rank) {
      // The last bucket has no upper edge: all it can say is the maximum.
      return b == kBuckets - 1 ? max_ : std::min(max_, sim::SimDuration{upper_edge(b)});
    }
  }
  return max_;
}

}  // namespace dxlemu::bus
