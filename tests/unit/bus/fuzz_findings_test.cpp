// Bus behaviours that fuzz_bus (tests/fuzz/) found wrong, each reproduced with the packet the
// fuzzer's input boiled down to.
#include <catch2/catch.hpp>

#include "bus_rig.hpp"

using namespace dxlemu;
using test::BusRig;
using test::kBroadcast;
using wire::Protocol;

TEST_CASE("A Fast read whose reply would not fit a 2.0 LENGTH goes unanswered", "[bus][fuzz]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 2);
  // One block of 65535 data bytes (a failed read is zero-filled to the requested length) or two
  // blocks that add up to more than 65535: LENGTH cannot announce the reply. Encoding it threw
  // std::invalid_argument out of Bus::receive, which ended the daemon.
  SECTION("Fast Sync Read") {
    CHECK_NOTHROW(rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{0, 0xFFFF, {1}}}}));
  }
  SECTION("Fast Bulk Read") {
    CHECK_NOTHROW(rig.send(
        {Protocol::V2, kBroadcast, wire::FastBulkRead{{{{1, 132, 0x8000}, {2, 132, 0x7FF0}}}}}));
  }
  rig.run();
  CHECK(rig.link.deliveries().empty());
  // The largest Fast read that fits is still answered.
  // (It takes over 11 s to cross the line at 57600 bps.)
  rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{0, 0xFFFF - 5, {1}}}});
  rig.run(std::chrono::seconds(20));
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes.size() == 7 + 0xFFFF);
}
