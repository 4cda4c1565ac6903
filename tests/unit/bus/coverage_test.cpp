// Rules of protocol1.md and protocol2.md that the bus implements and that no other bus test proved:
// byte-exact replies on the virtual clock for the 1.0 instructions, every error number and bit,
// Status Return Level 1, broadcast silence, Factory Reset / Reboot / Clear / Backup over the bus,
// deferred Return Delay Time, Baud Rate and Protocol Type, failing and duplicate slots of the group
// instructions, unicast group instructions, malformed packets, packets written in pieces, stuffing,
// damaged broadcasts, the 1.0 inter-byte timeout and same-ID collisions in broadcast Ping and
// group reads. The index of every rule and its test is docs/protocol-coverage.md. Expected bytes
// were computed independently of the encoder (CRC-16/0x8005 and the 1.0 checksum by hand), or
// copied from the e-Manual where it prints them.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "bus_rig.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using test::BusRig;
using test::kBroadcast;
using test::kXProcessing;
using test::kXReturnDelay;
using test::line;
using test::turn_by_hand;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

constexpr std::uint32_t kOneMbps = 1'000'000;
// A load that back-drives an XM430-W350 with torque off, and a few motion ticks.
constexpr double kHandTorqueNm = 2.0;
constexpr sim::SimDuration kMs = 5ms;

/// The client writes raw `bytes` now at `bps` (e.g. a packet printed by the e-Manual).
std::size_t feed(BusRig& rig, const Bytes& bytes, std::uint32_t bps = BusRig::kBaud) {
  rig.bus.receive(bytes, rig.scheduler.now(), bps);
  return bytes.size();
}

/// Sends `packet` with its last byte flipped (a wrong CRC or checksum).
void send_damaged(BusRig& rig, const wire::InstructionPacket& packet,
                  std::uint32_t bps = BusRig::kBaud) {
  auto bytes = wire::encode_instruction(packet);
  bytes.back() ^= 0x01;
  rig.bus.receive(bytes, rig.scheduler.now(), bps);
}

/// The bytes delivered to the client, oldest first.
std::vector<Bytes> delivered(const BusRig& rig) {
  std::vector<Bytes> out;
  for (const auto& d : rig.link.deliveries()) {
    out.push_back(d.bytes);
  }
  return out;
}

/// A Protocol 2.0 status of ID 1 with no parameters and error byte `error`: FF FF FD 00 01 04 00
/// 55 ERR CRC_L CRC_H. The CRCs were computed by hand for each error byte used here.
Bytes v2_status_id1(std::uint8_t error) {
  struct Known {
    std::uint8_t error;
    std::uint8_t crc_l;
    std::uint8_t crc_h;
  };
  static constexpr std::array<Known, 16> kKnown = {{{0x00, 0xA1, 0x0C},
                                                    {0x01, 0xA4, 0x8C},
                                                    {0x02, 0xAE, 0x8C},
                                                    {0x03, 0xAB, 0x0C},
                                                    {0x04, 0xBA, 0x8C},
                                                    {0x05, 0xBF, 0x0C},
                                                    {0x06, 0xB5, 0x0C},
                                                    {0x07, 0xB0, 0x8C},
                                                    {0x80, 0xA2, 0x8F},
                                                    {0x81, 0xA7, 0x0F},
                                                    {0x82, 0xAD, 0x0F},
                                                    {0x83, 0xA8, 0x8F},
                                                    {0x84, 0xB9, 0x0F},
                                                    {0x85, 0xBC, 0x8F},
                                                    {0x86, 0xB6, 0x8F},
                                                    {0x87, 0xB3, 0x0F}}};
  for (const Known& k : kKnown) {
    if (k.error == error) {
      return {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x55, error, k.crc_l, k.crc_h};
    }
  }
  FAIL("no expected packet for error byte " << int{error});
  return {};
}

// protocol2.md "Clear (0x10)" and "Control Table Backup (0x20)": option and fixed bytes.
const wire::Clear kClearMultiTurn{0x01, {0x44, 0x58, 0x4C, 0x22}};
const wire::ControlTableBackup kBackupStore{0x01, {0x43, 0x54, 0x52, 0x4C}};
const wire::ControlTableBackup kBackupRestore{0x02, {0x43, 0x54, 0x52, 0x4C}};

}  // namespace

// ---- Protocol 1.0 instructions ----

TEST_CASE(
    "Protocol 1.0 Ping, Read, Reg Write and Action reproduce the e-Manual examples on an "
    "RX-64",
    "[bus][timing]") {
  BusRig rig;  // RX-64 factory Baud Rate 34 is 57,600 bps in its table
  auto& servo = rig.add("rx-64", 1);
  servo.table().set("present_temperature", 0x20);
  // protocol1.md "Ping" example.
  const std::size_t sent = feed(rig, {0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB});
  rig.run();
  // protocol1.md "Read" example: Present Temperature (43).
  feed(rig, {0xFF, 0xFF, 0x01, 0x04, 0x02, 0x2B, 0x01, 0xCC});
  rig.run();
  // protocol1.md "Reg Write" example: 500 to Goal Position (30).
  feed(rig, {0xFF, 0xFF, 0x01, 0x05, 0x04, 0x1E, 0xF4, 0x01, 0xE2});
  rig.run();
  CHECK(servo.table().get("goal_position") == 512);
  CHECK(servo.table().get("registered") == 1);
  // protocol1.md "Action" example: broadcast, no status.
  feed(rig, {0xFF, 0xFF, 0xFE, 0x02, 0x05, 0xFA});
  rig.run();
  CHECK(servo.table().get("goal_position") == 500);
  CHECK(servo.table().get("registered") == 0);
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 3);
  CHECK(d[0].bytes == Bytes{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  CHECK(d[1].bytes == Bytes{0xFF, 0xFF, 0x01, 0x03, 0x00, 0x20, 0xDB});
  CHECK(d[2].bytes == Bytes{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  // RX-64: Ping processing 18 us, Return Delay Time 250 x 2 us.
  CHECK(d[0].at == sim::SimTime{} + line(sent) + 18us + 500us + line(6));
}

TEST_CASE("Protocol 1.0 broadcast Write sets the ID of an unknown servo without a status",
          "[bus]") {
  BusRig rig;
  auto& servo = rig.add("rx-64", 9);
  // protocol1.md "Write" example: ID broadcast, write 1 to ID (3).
  feed(rig, {0xFF, 0xFF, 0xFE, 0x04, 0x03, 0x03, 0x01, 0xF6});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(servo.id() == 1);
  feed(rig, {0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC}});
}

TEST_CASE("Protocol 1.0 Reg Write to 3 servos, then one broadcast Action applies them together",
          "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2, 3}) {
    rig.add("ax-12a", id);  // factory: 1 Mbps
    rig.send({Protocol::V1, id, wire::RegWrite{30, {0x00, 0x02}}}, kOneMbps);
    rig.run();
  }
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC},
                                             {0xFF, 0xFF, 0x02, 0x02, 0x00, 0xFB},
                                             {0xFF, 0xFF, 0x03, 0x02, 0x00, 0xFA}});
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("goal_position") == 512);
    CHECK(s->table().get("registered") == 1);
  }
  rig.link.clear();
  rig.send({Protocol::V1, kBroadcast, wire::Action{}}, kOneMbps);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("goal_position") == 0x200);
    CHECK(s->table().get("registered") == 0);
  }
  // Nothing is registered any more: Action is an Instruction Error (protocol1.md "Error").
  rig.send({Protocol::V1, 2, wire::Action{}}, kOneMbps);
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x02, 0x02, 0x40, 0xBB}});
}

TEST_CASE("Protocol 1.0 Factory Reset answers with the old ID and a broadcast one is ignored",
          "[bus]") {
  BusRig rig;
  auto& servo = rig.add("rx-64", 0);
  servo.table().set("return_delay_time", 0);
  servo.commit_deferred();
  // protocol1.md: "Broadcast ID(0xFE) cannot be used for Factory Reset instruction".
  feed(rig, {0xFF, 0xFF, 0xFE, 0x02, 0x06, 0xF9});
  rig.run(10ms);
  CHECK(rig.link.deliveries().empty());
  CHECK(servo.id() == 0);
  CHECK(servo.table().get("return_delay_time") == 0);
  CHECK_FALSE(rig.bus.booting(servo));
  // protocol1.md "Factory Reset" example: ID 0.
  feed(rig, {0xFF, 0xFF, 0x00, 0x02, 0x06, 0xF7});
  rig.run(10ms);
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x00, 0x02, 0x00, 0xFD}});
  CHECK(servo.id() == 1);
  CHECK(servo.return_delay() == 500us);
  CHECK(rig.bus.booting(servo));
}

TEST_CASE("Protocol 1.0 Reboot restarts an MX-28 and an X in 1.0 mode and an AX-12A refuses it",
          "[bus]") {
  BusRig rig;
  auto& mx = rig.add("mx-28", 1);  // 57,600 bps
  auto& x = rig.add("xm430-w210", 2);
  x.table().set("protocol_type", 1);
  x.commit_deferred();
  auto& ax = rig.add("ax-12a", 3);  // 1 Mbps
  for (auto* s : {&mx, &x, &ax}) {
    s->table().set("led", 1);
  }
  // protocol1.md "Reboot" example (XM430-W210, ID 1), here for ID 1 (MX-28) and ID 2.
  feed(rig, {0xFF, 0xFF, 0x01, 0x02, 0x08, 0xF4});
  rig.run(10ms);
  rig.send({Protocol::V1, 2, wire::Reboot{}});
  rig.run(10ms);
  rig.send({Protocol::V1, 3, wire::Reboot{}}, kOneMbps);
  rig.run(10ms);
  // "Supported products: MX-12W(V41), MX-28/64/106(V40), MX(2.0) and X Series".
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC},
                                             {0xFF, 0xFF, 0x02, 0x02, 0x00, 0xFB},
                                             {0xFF, 0xFF, 0x03, 0x02, 0x40, 0xBA}});
  CHECK(rig.bus.booting(mx));
  CHECK(rig.bus.booting(x));
  CHECK_FALSE(rig.bus.booting(ax));
  CHECK(mx.table().get("led") == 0);
  CHECK(x.table().get("led") == 0);
  CHECK(ax.table().get("led") == 1);
}

TEST_CASE("Protocol 1.0 Bulk Read is not answered by AX servos, which do not support it", "[bus]") {
  BusRig rig;
  auto& mx = rig.add("mx-28", 1);
  mx.table().set("baud_rate", 1);  // 1 Mbps, like the AX-12A
  mx.commit_deferred();
  rig.add("ax-12a", 2);
  rig.add("ax-12a", 3);
  rig.send({Protocol::V1, kBroadcast, wire::BulkRead{{{2, 43, 1}, {3, 43, 1}}}}, kOneMbps);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  // The MX-28 answers its block; the AX after it does not, so nothing follows.
  rig.send({Protocol::V1, kBroadcast, wire::BulkRead{{{1, 43, 1}, {2, 43, 1}}}}, kOneMbps);
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x03, 0x00, 0x19, 0xE2}});
}

// ---- Read and Write across items ----

TEST_CASE("Write and Read across several items in one packet, in both protocols", "[bus][timing]") {
  BusRig rig;
  auto& x = rig.add("xm430-w350", 1);
  // Profile Acceleration 10, Profile Velocity 200, Goal Position 1000 (108 ~ 119).
  const Bytes items = {10, 0, 0, 0, 200, 0, 0, 0, 0xE8, 0x03, 0, 0};
  const std::size_t write_size = rig.send({Protocol::V2, 1, wire::Write{108, items}});
  rig.run();
  const sim::SimTime read_at = rig.scheduler.now();
  const std::size_t read_size = rig.send({Protocol::V2, 1, wire::Read{108, 12}});
  rig.run();
  CHECK(x.table().get("profile_acceleration") == 10);
  CHECK(x.table().get("profile_velocity") == 200);
  CHECK(x.table().get("goal_position") == 1000);
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(d[0].bytes == v2_status_id1(0x00));
  CHECK(d[0].at == sim::SimTime{} + line(write_size) + kXProcessing + kXReturnDelay + line(11));
  CHECK(d[1].bytes == Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x10, 0x00, 0x55, 0x00, 0x0A, 0x00, 0x00,
                            0x00, 0xC8, 0x00, 0x00, 0x00, 0xE8, 0x03, 0x00, 0x00, 0x80, 0x46});
  CHECK(d[1].at == read_at + line(read_size) + kXProcessing + kXReturnDelay + line(23));

  BusRig v1;
  auto& ax = v1.add("ax-12a", 1);
  // Goal Position 0x200 and Moving Speed 0x150 in one Write.
  const std::size_t v1_size =
      v1.send({Protocol::V1, 1, wire::Write{30, {0x00, 0x02, 0x50, 0x01}}}, kOneMbps);
  v1.run();
  v1.send({Protocol::V1, 1, wire::Read{30, 4}}, kOneMbps);
  v1.run();
  CHECK(ax.table().get("goal_position") == 0x200);
  CHECK(ax.table().get("moving_speed") == 0x150);
  const auto& v1d = v1.link.deliveries();
  REQUIRE(v1d.size() == 2);
  CHECK(v1d[0].bytes == Bytes{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  // AX-12A write processing: 24 us + 6 us per data byte.
  CHECK(v1d[0].at ==
        sim::SimTime{} + line(v1_size, kOneMbps) + 24us + 4 * 6us + 500us + line(6, kOneMbps));
  CHECK(v1d[1].bytes == Bytes{0xFF, 0xFF, 0x01, 0x06, 0x00, 0x00, 0x02, 0x50, 0x01, 0xA5});
}

// ---- Errors ----

TEST_CASE(
    "Every 2.0 error number comes back over the bus, with the Alert bit while Hardware "
    "Error Status is set",
    "[bus]") {
  for (const bool alert : {false, true}) {
    CAPTURE(alert);
    const std::uint8_t a = alert ? 0x80 : 0x00;
    BusRig rig;
    auto& servo = rig.add("xm430-w350", 1);
    servo.table().set("hardware_error_status", alert ? 0x04 : 0x00);  // Overheating
    std::vector<std::uint8_t> expected;
    auto expect = [&](std::uint8_t error) {
      rig.run();
      expected.push_back(static_cast<std::uint8_t>(error | a));
    };
    // 0x01 Result Fail: Clear while moving (protocol2.md "Clear").
    turn_by_hand(servo, kHandTorqueNm);
    rig.run(kMs);
    rig.send({Protocol::V2, 1, kClearMultiTurn});
    expect(0x01);
    turn_by_hand(servo, 0);
    servo.table().set("present_position", 2048);
    // 0x02 Instruction Error: an undefined instruction, Action without Reg Write.
    rig.send({Protocol::V2, 1, wire::UnknownInstruction{0x7E, {}}});
    expect(0x02);
    rig.send({Protocol::V2, 1, wire::Action{}});
    expect(0x02);
    // 0x03 CRC Error.
    send_damaged(rig, {Protocol::V2, 1, wire::Read{132, 4}});
    expect(0x03);
    // 0x04 Data Range Error: ID 253 (0 ~ 252).
    rig.send({Protocol::V2, 1, wire::Write{7, {253}}});
    expect(0x04);
    // 0x05 Data Length Error: 2 bytes of the 4-byte Goal Position.
    rig.send({Protocol::V2, 1, wire::Write{116, {0x00, 0x01}}});
    expect(0x05);
    // 0x06 Data Limit Error: Goal Position beyond Max Position Limit.
    servo.table().set("max_position_limit", 3000);
    rig.send({Protocol::V2, 1, wire::Write{116, {0xFF, 0x0F, 0x00, 0x00}}});
    expect(0x06);
    // 0x07 Access Error: read-only item, read outside the table, EEPROM while torque is on.
    rig.send({Protocol::V2, 1, wire::Write{0, {0x00, 0x00}}});
    expect(0x07);
    rig.send({Protocol::V2, 1, wire::Read{700, 1}});
    expect(0x07);
    // After a hardware error shutdown Torque Enable is refused until a reboot (docs/motion.md).
    rig.send({Protocol::V2, 1, wire::Write{64, {1}}});
    expect(alert ? 0x01 : 0x00);
    servo.table().set("torque_enable", 1);
    rig.send({Protocol::V2, 1, wire::Write{9, {0}}});
    expect(0x07);
    std::vector<Bytes> packets;
    packets.reserve(expected.size());
    for (const std::uint8_t e : expected) {
      packets.push_back(v2_status_id1(e));
    }
    CHECK(delivered(rig) == packets);
    CHECK(servo.table().get("goal_position") == 2048);
    CHECK(servo.table().get("return_delay_time") == 250);
    rig.link.clear();
    rig.send({Protocol::V2, 1, wire::Ping{}});
    rig.run();
    CHECK(delivered(rig) ==
          std::vector<Bytes>{alert ? Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x80,
                                           0xFC, 0x03, 0x2D, 0x28, 0xC3}
                                   : Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00,
                                           0xFC, 0x03, 0x2D, 0x17, 0x43}});
  }
}

TEST_CASE(
    "Protocol 1.0 error bits come back over the bus: Instruction, Checksum, Range and Angle "
    "Limit",
    "[bus]") {
  BusRig rig;
  auto& servo = rig.add("ax-12a", 1);
  auto send = [&](const wire::Instruction& instruction) {
    rig.send({Protocol::V1, 1, instruction}, kOneMbps);
    rig.run();
  };
  send(wire::UnknownInstruction{0x07, {}});  // bit 6: undefined instruction
  send(wire::Action{});                      // bit 6: Action without Reg Write
  send_damaged(rig, {Protocol::V1, 1, wire::Read{43, 1}}, kOneMbps);  // bit 4
  rig.run();
  send(wire::Write{30, {0x00, 0x04}});         // bit 3: Goal Position 1024 (0 ~ 1023)
  send(wire::Read{48, 4});                     // bit 3: past the end of the table
  send(wire::Write{6, {200, 0, 0x20, 0x03}});  // CW Angle Limit 200, CCW Angle Limit 800
  send(wire::Write{30, {0x21, 0x03}});         // bit 1: Goal Position 801
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x40, 0xBC},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x40, 0xBC},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x10, 0xEC},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x08, 0xF4},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x08, 0xF4},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC},
                                             {0xFF, 0xFF, 0x01, 0x02, 0x02, 0xFA}});
  CHECK(servo.table().get("goal_position") == 512);
  CHECK(servo.table().get("cw_angle_limit") == 200);
  CHECK(servo.table().get("ccw_angle_limit") == 800);
}

TEST_CASE(
    "A malformed instruction is answered with Data Length Error, a bad option with Data "
    "Range Error, and a broadcast one not at all",
    "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  // A Read with 3 parameters instead of 4.
  feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x06, 0x00, 0x02, 0x84, 0x00, 0x04, 0x95, 0x7D});
  rig.run();
  // Factory Reset option 0x05 (only 0xFF, 0x01, 0x02 exist).
  feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x06, 0x05, 0xBA, 0x66});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, wire::UnknownInstruction{0x02, {0x84, 0x00, 0x04}}});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{v2_status_id1(0x05), v2_status_id1(0x04)});
  CHECK(rig.bus.stats().decode_errors == 3);
  CHECK(rig.bus.servos()[0]->id() == 1);

  // Protocol 1.0 has no length error: the Instruction Error bit (docs/servo.md).
  BusRig v1;
  v1.add("ax-12a", 1);
  feed(v1, {0xFF, 0xFF, 0x01, 0x03, 0x02, 0x2B, 0xCE}, kOneMbps);  // Read without its length
  v1.run();
  CHECK(delivered(v1) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x40, 0xBC}});
}

// ---- Status Return Level ----

TEST_CASE(
    "Status Return Level 1 over the bus answers Ping and Read only and still applies the "
    "rest",
    "[bus]") {
  BusRig rig;
  auto& x = rig.add("xm430-w350", 1);
  x.table().set("status_return_level", 1);
  rig.send({Protocol::V2, 1, wire::Write{65, {1}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::RegWrite{116, {0x00, 0x01, 0x00, 0x00}}});
  rig.run();
  CHECK(x.table().get("registered_instruction") == 1);
  rig.send({Protocol::V2, 1, wire::Action{}});
  rig.run();
  send_damaged(rig, {Protocol::V2, 1, wire::Write{65, {0}}});  // a damaged Write: no status
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(x.table().get("led") == 1);
  CHECK(x.table().get("goal_position") == 256);
  CHECK(x.table().get("registered_instruction") == 0);
  rig.send({Protocol::V2, 1, wire::Read{65, 1}});
  rig.run();
  send_damaged(rig, {Protocol::V2, 1, wire::Read{65, 1}});  // a damaged Read: CRC Error
  rig.run();
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  CHECK(delivered(rig) ==
        std::vector<Bytes>{
            {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x05, 0x00, 0x55, 0x00, 0x01, 0x56, 0xA1},
            v2_status_id1(0x03),
            {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0xFC, 0x03, 0x2D, 0x17, 0x43}});

  BusRig v1;
  auto& ax = v1.add("ax-12a", 1);
  ax.table().set("status_return_level", 1);
  v1.send({Protocol::V1, 1, wire::Write{25, {1}}}, kOneMbps);
  v1.run();
  CHECK(v1.link.deliveries().empty());
  CHECK(ax.table().get("led") == 1);
  v1.send({Protocol::V1, 1, wire::Read{25, 1}}, kOneMbps);
  v1.run();
  v1.send({Protocol::V1, 1, wire::Ping{}}, kOneMbps);
  v1.run();
  CHECK(delivered(v1) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x03, 0x00, 0x01, 0xFA},
                                            {0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC}});
}

TEST_CASE("A listed servo at Status Return Level 0 breaks the Sync Read chain", "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2, 3}) {
    rig.add("xm430-w350", id);
  }
  rig.bus.servos()[1]->table().set("status_return_level", 0);
  rig.send({Protocol::V2, kBroadcast, wire::SyncRead{146, 1, {1, 2, 3}}});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x05, 0x00, 0x55, 0x00,
                                              0x19, 0x06, 0xA1}});
}

TEST_CASE("Broadcast instructions other than Ping and the group reads execute without a status",
          "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2}) {
    rig.add("xm430-w350", id).table().set("present_position", 5000);
  }
  rig.send({Protocol::V2, kBroadcast, wire::Read{146, 1}});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, wire::UnknownInstruction{0x7E, {}}});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, wire::RegWrite{65, {1}}});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, kClearMultiTurn});
  rig.run();
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("registered_instruction") == 1);
    CHECK(s->table().get("present_position") == 5000 % 4096);
  }
  rig.send({Protocol::V2, kBroadcast, wire::Reboot{}});
  rig.run(10ms);
  CHECK(rig.link.deliveries().empty());
  for (const auto& s : rig.bus.servos()) {
    CHECK(rig.bus.booting(*s));
    CHECK(s->table().get("registered_instruction") == 0);  // the reboot emptied it
  }
  CHECK(rig.bus.stats().frames == 5);
}

// ---- Factory Reset, Reboot, Clear, Control Table Backup (2.0) ----

TEST_CASE(
    "Broadcast Factory Reset over the bus: 0xFF is not executed, 0x02 runs silently and "
    "reboots every servo",
    "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {3, 4}) {
    auto& s = rig.add("xm430-w350", id);
    s.table().set("return_delay_time", 0);
    s.commit_deferred();
  }
  rig.send({Protocol::V2, kBroadcast, wire::FactoryReset{wire::factory_reset::kResetAll}});
  rig.run(10ms);
  CHECK(rig.link.deliveries().empty());
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("return_delay_time") == 0);
    CHECK_FALSE(rig.bus.booting(*s));
  }
  rig.send(
      {Protocol::V2, kBroadcast, wire::FactoryReset{wire::factory_reset::kResetAllButIdAndBaud}});
  rig.run(10ms);
  rig.send({Protocol::V2, 3, wire::Ping{}});  // still booting
  rig.run(10ms);
  CHECK(rig.link.deliveries().empty());
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("return_delay_time") == 250);
    CHECK(rig.bus.booting(*s));
  }
  CHECK(rig.bus.servos()[0]->id() == 3);
  CHECK(rig.bus.servos()[1]->id() == 4);
  rig.run(500ms);
  const sim::SimTime ping_at = rig.scheduler.now();
  rig.send({Protocol::V2, 3, wire::Ping{}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x03, 0x07, 0x00, 0x55, 0x00, 0xFC, 0x03, 0x2D, 0x1B, 0x63});
  CHECK(rig.link.deliveries()[0].at ==
        ping_at + line(10) + kXProcessing + kXReturnDelay + line(14));
}

TEST_CASE(
    "Factory Reset 0x01 reproduces the e-Manual example and resets the Baud Rate but not "
    "the ID, 0x02 keeps both",
    "[bus]") {
  BusRig rig;
  auto& one = rig.add("xm430-w350", 1);
  auto& five = rig.add("xm430-w350", 5);
  for (auto* s : {&one, &five}) {
    s->table().set("baud_rate", 3);  // 1 Mbps
    s->commit_deferred();
  }
  // protocol2.md "Factory Reset (0x06)" example: ID 1, option 0x01.
  feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x04, 0x00, 0x06, 0x01, 0xA1, 0xE6}, kOneMbps);
  rig.run(10ms);
  rig.send({Protocol::V2, 5, wire::FactoryReset{wire::factory_reset::kResetAllButIdAndBaud}},
           kOneMbps);
  rig.run(10ms);
  CHECK(delivered(rig) ==
        std::vector<Bytes>{v2_status_id1(0x00),
                           {0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x04, 0x00, 0x55, 0x00, 0x42, 0x8D}});
  rig.run(1s);
  CHECK(one.id() == 1);
  CHECK(one.baud_bps() == 57'600);
  CHECK(five.id() == 5);
  CHECK(five.baud_bps() == kOneMbps);
  rig.link.clear();
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  rig.send({Protocol::V2, 5, wire::Ping{}}, kOneMbps);
  rig.run();
  CHECK(rig.link.deliveries().size() == 2);
}

TEST_CASE("A rebooted servo is silent for exactly its boot time after its status",
          "[bus][timing]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  // protocol2.md "Reboot (0x08)" example.
  feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x08, 0x2F, 0x4E});
  rig.run(10ms);
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes == v2_status_id1(0x00));
  const sim::SimTime booted = rig.link.deliveries()[0].at + 400ms;  // the model's boot_ms
  rig.link.clear();
  SECTION("a Ping that ends 1 ns before the boot is over is not heard") {
    rig.scheduler.advance_to(booted - line(10) - 1ns);
    CHECK(rig.bus.booting(servo));
    rig.send({Protocol::V2, 1, wire::Ping{}});
    rig.run(10ms);
    CHECK(rig.link.deliveries().empty());
  }
  SECTION("a Ping that ends when the boot is over is answered") {
    const sim::SimTime sent_at = booted - line(10);
    rig.scheduler.advance_to(sent_at);
    rig.send({Protocol::V2, 1, wire::Ping{}});
    rig.run(10ms);
    REQUIRE(rig.link.deliveries().size() == 1);
    CHECK(rig.link.deliveries()[0].at ==
          sent_at + line(10) + kXProcessing + kXReturnDelay + line(14));
  }
}

TEST_CASE(
    "Clear over the bus reproduces the e-Manual example and answers Result Fail while "
    "moving",
    "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  servo.table().set("present_position", 10000);
  // protocol2.md "Clear (0x10)" example.
  feed(rig,
       {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x10, 0x01, 0x44, 0x58, 0x4C, 0x22, 0xB1, 0xDC});
  rig.run();
  CHECK(servo.table().get("present_position") == 10000 % 4096);
  servo.table().set("present_position", 5000);
  turn_by_hand(servo, kHandTorqueNm);
  rig.run(kMs);
  rig.send({Protocol::V2, 1, kClearMultiTurn});
  rig.run();
  CHECK(servo.table().get("present_position") > 5000);  // still turning, not wrapped
  turn_by_hand(servo, 0);
  servo.table().set("present_position", 5000);
  rig.send({Protocol::V2, 1, wire::Clear{0x02, {}}});  // a reserved option
  rig.run();
  CHECK(servo.table().get("present_position") == 5000);
  CHECK(delivered(rig) ==
        std::vector<Bytes>{v2_status_id1(0x00), v2_status_id1(0x01), v2_status_id1(0x04)});
}

TEST_CASE(
    "Control Table Backup over the bus stores as in the e-Manual, restores and reboots "
    "after the status, and answers Result Fail with torque on",
    "[bus][timing]") {
  BusRig rig;
  auto& servo = rig.add("xc330-t288", 1);
  // protocol2.md "Control Table Backup (0x20)" Example 1.
  feed(rig,
       {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x20, 0x01, 0x43, 0x54, 0x52, 0x4C, 0x16, 0xF5});
  rig.run();
  CHECK(servo.table().get("backup_ready") == 1);
  rig.send({Protocol::V2, 1, wire::Write{9, {0}}});  // Return Delay Time 0
  rig.run();
  CHECK(servo.return_delay() == 0us);
  // Example 2 (restore): the page misprints its CRC (protocol2-crc.md); this is the correct one.
  const sim::SimTime restore_at = rig.scheduler.now();
  const std::size_t sent = feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x08, 0x00, 0x20, 0x02, 0x43,
                                      0x54, 0x52, 0x4C, 0x9E, 0xF5});
  rig.run(10ms);
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 3);
  // The restore's status still goes out with Return Delay Time 0, then the servo reboots.
  CHECK(d[2].at == restore_at + line(sent) + kXProcessing + line(11));
  CHECK(rig.bus.booting(servo));
  CHECK(servo.return_delay() == kXReturnDelay);
  rig.run(1s);
  servo.table().set("torque_enable", 1);
  rig.send({Protocol::V2, 1, kBackupStore});
  rig.run();
  rig.send({Protocol::V2, 1, kBackupRestore});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{v2_status_id1(0x00), v2_status_id1(0x00),
                                             v2_status_id1(0x00), v2_status_id1(0x01),
                                             v2_status_id1(0x01)});
  CHECK_FALSE(rig.bus.booting(servo));
}

// ---- Deferred identity ----

TEST_CASE("A packet written in pieces ends when the last byte of its last piece is through",
          "[bus][timing]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  servo.table().set("baud_rate", 3);  // 1 Mbps: 10 bytes take 100 us
  servo.commit_deferred();
  const auto bytes = wire::encode_instruction({Protocol::V2, 1, wire::Ping{}});
  rig.bus.receive(std::span(bytes).first(6), rig.scheduler.now(), kOneMbps);
  rig.run(1ms);  // within the 1.5 ms inter-byte timeout
  const sim::SimTime last_piece = rig.scheduler.now();
  rig.bus.receive(std::span(bytes).subspan(6), last_piece, kOneMbps);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  // The 4 bytes of the last piece follow each other on the line.
  CHECK(rig.link.deliveries()[0].at == last_piece + line(bytes.size() - 6, kOneMbps) +
                                           kXProcessing + kXReturnDelay + line(14, kOneMbps));
}

TEST_CASE(
    "A new Return Delay Time applies from the next reply, not to the status of the Write "
    "that set it",
    "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  const std::size_t write_size = rig.send({Protocol::V2, 1, wire::Write{9, {0}}});
  rig.run();
  const sim::SimTime ping_at = rig.scheduler.now();
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(d[0].bytes == v2_status_id1(0x00));
  CHECK(d[0].at == sim::SimTime{} + line(write_size) + kXProcessing + kXReturnDelay + line(11));
  CHECK(d[1].at == ping_at + line(10) + kXProcessing + line(14));
}

TEST_CASE("A new Baud Rate applies after its status, which goes out at the old rate",
          "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  const std::size_t write_size = rig.send({Protocol::V2, 1, wire::Write{8, {3}}});
  rig.run();
  const sim::SimTime ping_at = rig.scheduler.now();
  rig.send({Protocol::V2, 1, wire::Ping{}}, kOneMbps);
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(d[0].at == sim::SimTime{} + line(write_size) + kXProcessing + kXReturnDelay + line(11));
  CHECK(d[1].at ==
        ping_at + line(10, kOneMbps) + kXProcessing + kXReturnDelay + line(14, kOneMbps));
}

TEST_CASE(
    "A Protocol Type change to 1.0 is confirmed in 2.0, then the servo answers only "
    "Protocol 1.0",
    "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{13, {1}}});
  CHECK(servo.protocol() == Protocol::V2);
  rig.run();
  CHECK(servo.protocol() == Protocol::V1);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  rig.send({Protocol::V1, 1, wire::Ping{}});
  rig.run();
  CHECK(delivered(rig) ==
        std::vector<Bytes>{v2_status_id1(0x00), {0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC}});
}

TEST_CASE("A client within 3 percent of a servo's baud rate is heard and one beyond is not",
          "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);                           // 57,600 bps
  rig.send({Protocol::V2, 1, wire::Ping{}}, 59'000);  // +2.4 %
  rig.run();
  rig.send({Protocol::V2, 1, wire::Ping{}}, 56'000);  // -2.8 %
  rig.run();
  CHECK(rig.link.deliveries().size() == 2);
  rig.send({Protocol::V2, 1, wire::Ping{}}, 60'000);  // +4.2 %
  rig.run();
  rig.send({Protocol::V2, 1, wire::Ping{}}, 55'500);  // -3.6 %
  rig.run();
  CHECK(rig.link.deliveries().size() == 2);
}

// ---- Group reads ----

TEST_CASE("A Sync Read slot whose read fails carries the error and the chain goes on",
          "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xc330-t288", 2);  // its table ends at 251
  rig.add("xm430-w350", 3);
  // Indirect Address 40 (600) holds 645 = 0x0285 at the factory on XM430.
  const std::size_t sent = rig.send({Protocol::V2, kBroadcast, wire::SyncRead{600, 2, {1, 2, 3}}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 3);
  CHECK(d[0].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x06, 0x00, 0x55, 0x00, 0x85, 0x02, 0xC0, 0xC5});
  CHECK(d[1].bytes == Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x04, 0x00, 0x55, 0x07, 0x38, 0x8C});
  CHECK(d[2].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x03, 0x06, 0x00, 0x55, 0x00, 0x85, 0x02, 0xE3, 0x47});
  const auto step = kXProcessing + kXReturnDelay;
  CHECK(d[0].at == sim::SimTime{} + line(sent) + step + line(13));
  CHECK(d[1].at == d[0].at + step + line(11));
  CHECK(d[2].at == d[1].at + step + line(13));
}

TEST_CASE("A Fast Sync Read block whose read fails carries the error and zeros", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xc330-t288", 2);
  rig.add("xm430-w350", 3);
  rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{600, 2, {1, 2, 3}}}});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x13, 0x00, 0x55, 0x00,
                                              0x01, 0x85, 0x02, 0xB8, 0x3C, 0x07, 0x02, 0x00, 0x00,
                                              0x45, 0x31, 0x00, 0x03, 0x85, 0x02, 0x28, 0x69}});
}

TEST_CASE(
    "A Bulk Read that lists an ID twice is answered by its first block only, in both "
    "protocols",
    "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 2);
  rig.send({Protocol::V2, kBroadcast, wire::BulkRead{{{1, 146, 1}, {2, 146, 1}, {1, 0, 2}}}});
  rig.run();
  CHECK(
      delivered(rig) ==
      std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x05, 0x00, 0x55, 0x00, 0x19, 0x06, 0xA1},
                         {0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x05, 0x00, 0x55, 0x00, 0x19, 0x06, 0x29}});

  // protocol1.md "Bulk Read": "only the first designated parameter will be processed".
  BusRig v1;
  v1.add("mx-28", 1);
  v1.add("mx-28", 2);
  v1.send({Protocol::V1, kBroadcast, wire::BulkRead{{{1, 43, 1}, {2, 43, 1}, {1, 30, 2}}}});
  v1.run();
  CHECK(delivered(v1) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x03, 0x00, 0x19, 0xE2},
                                            {0xFF, 0xFF, 0x02, 0x03, 0x00, 0x19, 0xE1}});
}

TEST_CASE("A Sync Read that lists an ID twice is answered once per servo, Fast or not", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 2);
  rig.send({Protocol::V2, kBroadcast, wire::SyncRead{146, 1, {1, 2, 1}}});
  rig.run();
  CHECK(
      delivered(rig) ==
      std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x05, 0x00, 0x55, 0x00, 0x19, 0x06, 0xA1},
                         {0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x05, 0x00, 0x55, 0x00, 0x19, 0x06, 0x29}});
  BusRig fast;
  fast.add("xm430-w350", 1);
  fast.add("xm430-w350", 2);
  fast.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{146, 1, {2, 1, 2}}}});
  fast.run();
  REQUIRE(fast.link.deliveries().size() == 1);
  // Two blocks of error, ID, 1 byte, CRC after the 8-byte head: LENGTH 1 + 2 * 5.
  const Bytes& reply = fast.link.deliveries()[0].bytes;
  CHECK(reply.size() == 8 + 2 * 5);
  CHECK(reply[5] == 1 + 2 * 5);
  CHECK(reply[9] == 2);
  CHECK(reply[14] == 1);
}

TEST_CASE("A Bulk Write that lists an ID twice applies its first block only", "[bus]") {
  BusRig rig;
  auto& one = rig.add("xm430-w350", 1);
  auto& two = rig.add("xm430-w350", 2);
  // protocol2.md "Bulk Write (0x93)": "The same ID cannot be used multiple times".
  rig.send({Protocol::V2, kBroadcast,
            wire::BulkWrite{{{1, 65, {1}}, {2, 65, {1}}, {1, 116, {0x00, 0x04, 0x00, 0x00}}}}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(one.table().get("led") == 1);
  CHECK(two.table().get("led") == 1);
  CHECK(one.table().get("goal_position") == 2048);
}

TEST_CASE("Sync and Bulk instructions sent to a unicast ID are ignored", "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xc330-t288", 1);
  rig.send({Protocol::V2, 1, wire::SyncRead{146, 1, {1}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::BulkRead{{{1, 146, 1}}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::FastSyncRead{{146, 1, {1}}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::FastBulkRead{{{{1, 146, 1}}}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::SyncWrite{65, 1, {{1, {1}}}}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::BulkWrite{{{1, 65, {1}}}}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(servo.table().get("led") == 0);
  CHECK(rig.bus.stats().frames == 6);
  CHECK(rig.bus.stats().decode_errors == 0);

  BusRig v1;
  auto& mx = v1.add("mx-28", 1);
  v1.send({Protocol::V1, 1, wire::BulkRead{{{1, 43, 1}}}});
  v1.run();
  v1.send({Protocol::V1, 1, wire::SyncWrite{25, 1, {{1, {1}}}}});
  v1.run();
  CHECK(v1.link.deliveries().empty());
  CHECK(mx.table().get("led") == 0);
}

// ---- Collisions ----

// protocol2.md "ID": "If DYNAMIXELs with the same ID are connected, packet collision and network
// problems will occur" (protocol1.md "DYNAMIXEL Protocol" alike): two servos configured with the
// same ID both answer and their bytes collide. The bus garbles a unicast reply that way
// (docs/bus.md "Collisions"); these two tests expect the same for the replies of a broadcast Ping
// and of a Sync Read slot, where the bus currently lets one or both answer cleanly.
TEST_CASE("Two servos with the same ID collide in a broadcast Ping as in a unicast instruction",
          "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);  // model number 1020 = 0x03FC
  rig.add("xm430-w210", 1);  // model number 1030 = 0x0406
  rig.send({Protocol::V2, kBroadcast, wire::Ping{}});
  rig.run();
  // The two Ping replies ANDed on the line: FC & 06, 03 & 04, and their CRCs.
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00,
                                              0x04, 0x00, 0x2D, 0x14, 0x41}});
  CHECK(rig.bus.stats().id_conflicts == 1);
}

TEST_CASE("Two servos with the same ID collide in their Sync Read slot", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1).table().set("present_temperature", 0x21);
  rig.add("xm430-w350", 1).table().set("present_temperature", 0x12);
  rig.send({Protocol::V2, kBroadcast, wire::SyncRead{146, 1, {1}}});
  rig.run();
  // 0x21 & 0x12 = 0x00, and the two CRCs ANDed: the client sees a damaged packet.
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x05, 0x00, 0x55, 0x00,
                                              0x00, 0x15, 0x21}});
  CHECK(rig.bus.stats().id_conflicts == 1);
}

// ---- Framing ----

TEST_CASE("A Write and a Read whose data hold FF FF FD are stuffed on the wire both ways",
          "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  // Homing Offset (20) = 0xFFFDFFFF = -131073: the instruction arrives stuffed (LENGTH 10).
  feed(rig, {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x0A, 0x00, 0x03, 0x14, 0x00, 0xFF, 0xFF, 0xFD, 0xFD,
             0xFF, 0x23, 0x83});
  rig.run();
  CHECK(servo.table().get("homing_offset") == -131073);
  rig.send({Protocol::V2, 1, wire::Read{20, 4}});
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{v2_status_id1(0x00),
                                             {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x09, 0x00, 0x55, 0x00,
                                              0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0xDA, 0x9E}});
}

TEST_CASE("A damaged broadcast packet is not answered", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("ax-12a", 2).table().set("baud_rate", 34);
  rig.bus.servos()[1]->commit_deferred();
  send_damaged(rig, {Protocol::V2, kBroadcast, wire::Ping{}});
  rig.run();
  send_damaged(rig, {Protocol::V1, kBroadcast, wire::Ping{}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.stats().bad_checks == 2);
}

TEST_CASE("A partial Protocol 1.0 packet is dropped after 100 ms of quiet on the bus",
          "[bus][timing]") {
  BusRig rig;
  rig.add("ax-12a", 1);
  const auto bytes = wire::encode_instruction({Protocol::V1, 1, wire::Ping{}});
  rig.bus.receive(std::span(bytes).first(4), rig.scheduler.now(), kOneMbps);
  rig.run(100ms);
  CHECK(rig.bus.stats().truncated == 0);
  rig.run(1ms);
  CHECK(rig.bus.stats().truncated == 1);
  rig.bus.receive(bytes, rig.scheduler.now(), kOneMbps);
  rig.run();
  CHECK(delivered(rig) == std::vector<Bytes>{{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC}});
}
