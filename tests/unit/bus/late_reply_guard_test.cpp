#include "bus/late_reply_guard.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <string>
#include <vector>

#include "bus/lateness_histogram.hpp"
#include "bus/loopback_link.hpp"

namespace {

using dxlemu::bus::LatenessHistogram;
using dxlemu::bus::LatenessSummary;
using dxlemu::bus::LateReplyGuard;
using dxlemu::bus::LateReplyPolicy;
using dxlemu::bus::LoopbackLink;
using dxlemu::sim::SimDuration;
using dxlemu::sim::SimTime;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::seconds;

const std::vector<std::uint8_t> kReply{0xFF, 0xFF, 0xFD, 0x00, 0x01};
constexpr std::uint32_t kBps = 1'000'000;  // the guard passes the line rate on untouched

// A guard on a loopback link whose clock the test sets.
struct Rig {
  LoopbackLink link;
  SimTime now{};
  std::vector<std::string> warnings;
  LateReplyGuard guard;

  explicit Rig(LateReplyPolicy policy = {})
      : guard(
            link, [this] { return now; }, policy,
            [this](const std::string& message) { warnings.push_back(message); }) {}

  // Delivers kReply modelled for `at` while the clock reads `at + late`.
  bool deliver_late(SimTime at, SimDuration late) {
    now = at + late;
    return guard.deliver(kReply, at, kBps);
  }
};

}  // namespace

TEST_CASE("Replies on time or a little late pass the guard unchanged", "[bus][lateness]") {
  Rig rig;
  const SimTime at = SimTime{} + milliseconds(5);
  CHECK(rig.deliver_late(at, SimDuration{0}));
  CHECK(rig.deliver_late(at + milliseconds(1), microseconds(900)));
  REQUIRE(rig.link.deliveries().size() == 2);
  CHECK(rig.link.deliveries()[0] == LoopbackLink::Delivery{kReply, at});
  CHECK(rig.link.deliveries()[1].at == at + milliseconds(1));  // the modelled time, passed on
  const LatenessSummary s = rig.guard.summary();
  CHECK(s.deliveries == 2);
  CHECK(s.dropped == 0);
  CHECK(s.over[0] == 0);
  CHECK(s.max == microseconds(900));
  CHECK(rig.warnings.empty());
}

TEST_CASE("A reply later than the bound is dropped and counted, not sent", "[bus][lateness]") {
  Rig rig;  // the default: drop after 20 ms
  const SimTime at = SimTime{} + seconds(1);
  CHECK(rig.deliver_late(at, milliseconds(20)));  // exactly the bound: still sent
  CHECK(rig.deliver_late(at, milliseconds(41)));  // the client stopped waiting long ago
  CHECK(rig.link.deliveries().size() == 1);
  const LatenessSummary s = rig.guard.summary();
  CHECK(s.deliveries == 2);
  CHECK(s.dropped == 1);
  CHECK(s.over == std::array<std::uint64_t, 4>{2, 2, 2, 1});
  CHECK(s.max == milliseconds(41));
  CHECK(s.drop_after == milliseconds(20));
}

TEST_CASE("With a bound of zero nothing is dropped", "[bus][lateness]") {
  LateReplyPolicy policy;
  policy.drop_after = SimDuration{0};
  Rig rig(policy);
  CHECK(rig.deliver_late(SimTime{}, seconds(2)));
  CHECK(rig.link.deliveries().size() == 1);
  CHECK(rig.guard.summary().dropped == 0);
}

TEST_CASE("A full link still reports its refusal through the guard", "[bus][lateness]") {
  Rig rig;
  rig.link.set_accepting(false);
  CHECK_FALSE(rig.deliver_late(SimTime{}, SimDuration{0}));
}

TEST_CASE("Late replies are warned about at most once per interval, summed", "[bus][lateness]") {
  Rig rig;  // warn after 2 ms, at most every 5 s; drop after 20 ms
  rig.deliver_late(SimTime{} + seconds(1), milliseconds(3));
  REQUIRE(rig.warnings.size() == 1);
  CHECK(rig.warnings[0] ==
        "1 reply went out more than 2.0 ms later than a servo would send it (at most 3.0 ms late; "
        "0 later than 20.0 ms dropped instead): dxlemu did not get a CPU in time, the machine is "
        "overloaded (see docs/timing.md \"Late replies\"; --realtime-priority helps)");
  rig.deliver_late(SimTime{} + seconds(2), milliseconds(30));
  rig.deliver_late(SimTime{} + seconds(3), milliseconds(1));  // not late enough to count
  rig.deliver_late(SimTime{} + seconds(4), milliseconds(4));
  CHECK(rig.warnings.size() == 1);
  rig.deliver_late(SimTime{} + seconds(6), milliseconds(5));  // 5 s after the first warning
  REQUIRE(rig.warnings.size() == 2);
  CHECK(rig.warnings[1].rfind("3 replies went out more than 2.0 ms later than a servo would send "
                              "them (at most 30.0 ms late; 1 later than 20.0 ms dropped instead)",
                              0) == 0);
}

TEST_CASE("The lateness histogram's percentiles are within a bucket of the truth",
          "[bus][lateness]") {
  LatenessHistogram h;
  CHECK(h.percentile(0.5) == SimDuration{0});
  for (int us = 1; us <= 1000; ++us) {
    h.add(microseconds(us));
  }
  h.add(microseconds(-3));  // counts as zero
  CHECK(h.count() == 1001);
  CHECK(h.max() == microseconds(1000));
  const auto near = [](SimDuration got, SimDuration want) {
    // One bucket is 1/16 of its power of two: within 6.25 % above the truth, never below it.
    return got >= want && got <= want + want / LatenessHistogram::kSubBuckets;
  };
  CHECK(near(h.percentile(0.5), microseconds(500)));
  CHECK(near(h.percentile(0.99), microseconds(990)));
  CHECK(h.percentile(1.0) == microseconds(1000));  // never beyond the maximum
  CHECK(h.percentile(0.0) < microseconds(2));
  LatenessHistogram huge;
  huge.add(std::chrono::hours(5));  // beyond the last octave: the last bucket, max exact
  CHECK(huge.percentile(0.5) == std::chrono::hours(5));
}
