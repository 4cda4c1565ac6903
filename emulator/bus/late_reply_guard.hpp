#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "bus/byte_link.hpp"
#include "bus/lateness_histogram.hpp"

namespace dxlemu::bus {

/// What the guard does with late replies (docs/timing.md "Late replies").
struct LateReplyPolicy {
  /// A delivery later than this against its modelled time is dropped instead of sent; zero
  /// never drops. The default is well under the 34 ms a DynamixelSDK client waits for a short
  /// status (twice its 16 ms latency timer and 2 ms), leaving 14 ms for the client's own late
  /// wake-up on the machine that made the reply late, and far over what a machine that keeps up
  /// adds (tens of µs).
  sim::SimDuration drop_after = std::chrono::milliseconds(20);
  /// A delivery later than this is worth a warning.
  sim::SimDuration warn_after = std::chrono::milliseconds(2);
  /// At most one warning per this much time; the late ones in between are summed into the next.
  sim::SimDuration warn_interval = std::chrono::seconds(5);
};

/// How late one port's deliveries went out, since the port was made.
struct LatenessSummary {
  /// The thresholds of `over`, in order.
  static constexpr std::array<std::chrono::milliseconds, 4> kThresholds{
      std::chrono::milliseconds(1), std::chrono::milliseconds(5), std::chrono::milliseconds(10),
      std::chrono::milliseconds(34)};
  std::uint64_t deliveries = 0;  ///< every delivery measured, the dropped ones included
  std::uint64_t dropped = 0;     ///< later than the policy's drop_after: not sent
  std::array<std::uint64_t, kThresholds.size()> over{};  ///< later than each threshold
  sim::SimDuration p50{0};
  sim::SimDuration p99{0};
  sim::SimDuration max{0};
  sim::SimDuration drop_after{0};  ///< the policy's bound; zero: none
};

/// Stands between a bus and its client's link and measures how late every delivery is: the
/// present (`now`, which the daemon reads off the wall clock) minus the time the bus modelled for
/// it. A real servo is never late; an emulator on a busy machine can be, and a reply that comes
/// after the client stopped waiting would be taken for the answer to its next request. So a
/// delivery later than the policy's bound is dropped and counted, as if it were lost on the line,
/// and late ones are reported through `warn`, at most once per warn_interval.
class LateReplyGuard : public ByteLink {
 public:
  /// The present, on the same scale as the times deliveries are modelled for.
  using Clock = std::function<sim::SimTime()>;
  /// Receives one warning message (without the port's name).
  using Warn = std::function<void(const std::string&)>;

  /// Guards `next`, which must outlive the guard.
  LateReplyGuard(ByteLink& next, Clock now, LateReplyPolicy policy, Warn warn);

  /// Hands `bytes` to the next link unless they are later than the policy allows. A dropped
  /// delivery counts as delivered (true): the client was reading, the bytes were lost.
  bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at, std::uint32_t bps) override;

  /// The figures so far.
  LatenessSummary summary() const;

 private:
  void note_late(sim::SimDuration lateness, bool dropped, sim::SimTime now);

  ByteLink& next_;
  Clock now_;
  LateReplyPolicy policy_;
  Warn warn_;
  LatenessHistogram histogram_;
  std::uint64_t dropped_ = 0;
  std::array<std::uint64_t, LatenessSummary::kThresholds.size()> over_{};
  // Late deliveries not yet reported, and when the last warning went out.
  std::uint64_t unreported_late_ = 0;
  std::uint64_t unreported_dropped_ = 0;
  sim::SimDuration unreported_max_{0};
  std::optional<sim::SimTime> last_warning_;
};

}  // namespace dxlemu::bus
