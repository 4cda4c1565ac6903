// The families and models beyond the first servos (docs/families.md): DX follows the RX rules,
// PRO(A) the P rules without Fast Read, the RH-P12-RN grippers their own modes and stroke,
// XM335-T323 its 1 Mbps factory rate, and models that share another's number report it.
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

/// The one status the client received, as describe() prints it.
std::string only_status(const BusRig& rig, Protocol protocol = Protocol::V2) {
  const auto& d = rig.link.deliveries();
  return d.size() == 1 ? test::status_text(d[0].bytes, protocol) : "not one reply";
}

}  // namespace

TEST_CASE("DX servos follow the RX rules: no Reboot, goals within the angle limits", "[bus]") {
  BusRig rig;
  rig.add("dx-117", 1);
  rig.send({Protocol::V1, 1, wire::Reboot{}});
  rig.run();
  CHECK(only_status(rig, Protocol::V1) == "id=1 error=0x40");  // Instruction Error

  BusRig limits;
  auto& dx = limits.add("dx-117", 1);
  dx.table().set("ccw_angle_limit", 800);
  dx.commit_deferred();
  limits.send({Protocol::V1, 1, wire::Write{30, {0x84, 0x03}}});  // Goal Position 900 > 800
  limits.run();
  CHECK(only_status(limits, Protocol::V1) == "id=1 error=0x02");  // Angle Limit Error
}

TEST_CASE("PRO(A) servos answer no Fast Sync Read, the P servos and RH-P12-RN(A) do", "[bus]") {
  for (const auto& [name, answers] :
       {std::pair{"h54-200-s500-ra", false}, std::pair{"ph54-200-s500-r", true},
        std::pair{"rh-p12-rna", true}}) {
    CAPTURE(name);
    BusRig rig;
    rig.add(name, 1);
    rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{580, 4, {1}}}});
    rig.run();
    CHECK(rig.link.deliveries().size() == (answers ? 1U : 0U));
  }
}

TEST_CASE("PRO(A) reports its own model number and the P rules' extended goals", "[bus]") {
  BusRig rig;
  auto& servo = rig.add("h54-200-s500-ra", 1);
  CHECK(servo.table().get("model_number") == 54025);
  CHECK(servo.spec().traits().extended_goals == model::ExtendedGoals::ItemWidth);
  rig.send({Protocol::V2, 1, wire::Read{0, 2}});
  rig.run();
  CHECK(only_status(rig) == "id=1 error=0x00 params=09 D3");
}

TEST_CASE("PRO(A) and the older P pages' misspelt Sencondary ID is the Secondary ID", "[bus]") {
  for (const char* name : {"h54-200-s500-ra", "ph42-020-s300-r"}) {
    CAPTURE(name);
    BusRig rig;
    rig.add(name, 1).table().set("secondary_id", 9);
    rig.send({Protocol::V2, 9, wire::Write{513, {200}}});  // LED Red, silently through the group
    rig.run();
    CHECK(rig.link.deliveries().empty());
    CHECK(rig.bus.servos()[0]->table().get("led_red") == 200);
  }
}

TEST_CASE("The RH-P12-RN grippers take only current and current-based position modes", "[bus]") {
  for (const char* name : {"rh-p12-rn", "rh-p12-rna"}) {
    CAPTURE(name);
    BusRig rig;
    auto& gripper = rig.add(name, 1);
    CHECK(gripper.table().get("operating_mode") == 5);
    rig.send({Protocol::V2, 1, wire::Write{11, {1}}});  // velocity mode: Reserved on a gripper
    rig.run();
    CHECK(only_status(rig) == "id=1 error=0x04");  // Data Range Error
    CHECK(gripper.table().get("operating_mode") == 5);
  }
}

TEST_CASE("An RH-P12-RN closes over its stroke and no further", "[bus][motion]") {
  BusRig rig;
  rig.add("rh-p12-rn", 1);
  const std::uint16_t torque_enable = 562;
  const std::uint16_t goal_position = 596;
  rig.send({Protocol::V2, 1, wire::Write{goal_position, le32(1151)}});  // past Max Position 1150
  rig.run();
  CHECK(only_status(rig) == "id=1 error=0x04");

  // Goal Current starts at 0 (the page's factory value), which grips with no force: a client
  // sets it before closing.
  BusRig closing;
  auto& g = closing.add("rh-p12-rn", 1);
  closing.send({Protocol::V2, 1, wire::Write{604, {0x90, 0x01}}});  // Goal Current 400
  closing.run(10ms);
  closing.send({Protocol::V2, 1, wire::Write{torque_enable, {1}}});
  closing.run(10ms);
  closing.send({Protocol::V2, 1, wire::Write{goal_position, le32(1150)}});
  closing.run(3s);
  g.advance_to(closing.scheduler.now());  // the motion model runs when the bus looks
  CHECK(g.table().get("present_position") >= 1148);
  CHECK(g.table().get("present_position") <= 1150);
  CHECK(g.table().get("moving") == 0);
}

TEST_CASE("XM335-T323 starts at 1 Mbps with the X330 Indirect block", "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm335-t323", 1);
  CHECK(servo.table().get("baud_rate") == 3);
  REQUIRE(servo.spec().indirect.size() == 1);
  CHECK(servo.spec().indirect[0].count == 28);
  rig.send({Protocol::V2, 1, wire::Ping{}}, 1'000'000);
  rig.run();
  CHECK(only_status(rig) == "id=1 error=0x00 params=AE 06 2E");  // 1710, firmware 46
}

TEST_CASE("The ball-bearing XC430 reports the number ROBOTIS gave it, XC430-W150's", "[bus]") {
  BusRig rig;
  rig.add("xc430-t150bb", 1);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  CHECK(only_status(rig).rfind("id=1 error=0x00 params=2E 04", 0) == 0);  // 1070
  CHECK(test::shipped_model("xc430-t150bb")->shares_model_number_with == "xc430-w150");
}

TEST_CASE("An L42-10-S300-R turns within one turn of 4,096 pulses, up to its position limits",
          "[bus][motion]") {
  BusRig rig;
  auto& servo = rig.add("l42-10-s300-r", 1);
  rig.send({Protocol::V2, 1, wire::Write{596, le32(2049)}});  // beyond Max Position Limit 2,048
  rig.run();
  CHECK(only_status(rig) == "id=1 error=0x06");  // Data Limit Error

  BusRig moving;
  auto& l42 = moving.add("l42-10-s300-r", 1);
  moving.send({Protocol::V2, 1, wire::Write{562, {1}}});  // Torque Enable
  moving.run(10ms);
  moving.send({Protocol::V2, 1, wire::Write{596, le32(-1024)}});  // a quarter turn back
  moving.run(3s);
  l42.advance_to(moving.scheduler.now());
  CHECK(l42.table().get("present_position") >= -1026);
  CHECK(l42.table().get("present_position") <= -1022);
  CHECK(servo.spec().motion.degrees_per_pulse == Approx(360.0 / 4096));
}
