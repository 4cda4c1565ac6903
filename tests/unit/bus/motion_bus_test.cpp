// Servos moving on a bus (docs/motion.md): what a client polling over the line sees, and that
// two runs of the same traffic give the same bytes at the same times.
#include <catch2/catch.hpp>

#include <chrono>

#include "bus_rig.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using test::BusRig;
using test::kBroadcast;
using test::le32;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

/// Three XM430-W350 on a 1 Mbps bus: profiles, a Sync Write of goals, a velocity override, a
/// blocked servo, and a Sync Read of Present Position every 10 ms for 3 s.
std::vector<bus::LoopbackLink::Delivery> run_script() {
  constexpr std::uint32_t kBps = 1'000'000;
  BusRig rig;
  for (std::uint8_t id = 1; id <= 3; ++id) {
    auto& servo = rig.add("xm430-w350", id);
    servo.table().set("baud_rate", 3);
    servo.commit_deferred();
  }
  rig.send({Protocol::V2, kBroadcast, wire::Write{112, le32(120)}}, kBps);  // Profile Velocity
  rig.send({Protocol::V2, kBroadcast, wire::Write{108, le32(15)}}, kBps);   // Profile Acceleration
  rig.send({Protocol::V2, kBroadcast, wire::Write{64, {1}}}, kBps);         // Torque Enable
  rig.run(3ms);
  rig.send({Protocol::V2, kBroadcast,
            wire::SyncWrite{116, 4, {{1, le32(3000)}, {2, le32(500)}, {3, le32(2100)}}}},
           kBps);
  model::Conditions blocked = rig.bus.servos()[2]->motion().conditions();
  blocked.blocked = true;
  rig.bus.servos()[2]->motion().set_conditions(blocked);
  for (int i = 0; i < 300; ++i) {
    rig.run(10ms);
    if (i == 40) {
      rig.send({Protocol::V2, 1, wire::Write{116, le32(1000)}}, kBps);  // override mid-move
      rig.run(1ms);
    }
    rig.send({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {1, 2, 3}}}, kBps);
  }
  rig.run();
  return rig.link.deliveries();
}

}  // namespace

TEST_CASE("Two runs of the same traffic give the same replies at the same times", "[bus][motion]") {
  const auto first = run_script();
  const auto second = run_script();
  REQUIRE(first.size() > 900);
  CHECK(first == second);
}

TEST_CASE("A client polling Present Position sees a profiled move progress and end",
          "[bus][motion]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{112, le32(100)}});  // Profile Velocity
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{108, le32(20)}});  // Profile Acceleration
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{64, {1}}});
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{116, le32(3048)}});
  std::vector<std::int64_t> seen;
  for (int i = 0; i < 100; ++i) {
    rig.run(20ms);
    rig.link.clear();
    rig.send({Protocol::V2, 1, wire::Read{132, 4}});
    rig.run(10ms);
    REQUIRE(rig.link.deliveries().size() == 1);
    const auto& bytes = rig.link.deliveries()[0].bytes;
    REQUIRE(bytes.size() == 15);
    seen.push_back(static_cast<std::int32_t>(bytes[9] | bytes[10] << 8 | bytes[11] << 16 |
                                             static_cast<std::uint32_t>(bytes[12]) << 24));
  }
  CHECK(std::is_sorted(seen.begin(), seen.end()));
  CHECK(seen.front() > 2048);
  CHECK(seen.front() < 2100);
  CHECK(seen.back() == 3048);
  CHECK(servo.table().get("moving") == 0);
}
