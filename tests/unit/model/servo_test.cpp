// One virtual servo executing instructions addressed to it (model/servo.hpp) on shipped models:
// replies, error bytes in both protocols, Status Return Level, broadcast rules, Reg Write/Action,
// Factory Reset, Reboot, deferred identity, Alert, Clear and Control Table Backup
// (protocol1.md, protocol2.md, README "Behaviours an emulator must honour").
#include <catch2/catch.hpp>

#include <chrono>

#include "model/servo.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using model::Servo;
using model::ServoResponse;
using std::chrono::microseconds;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::shared_ptr<const model::ModelSpec> shipped(const std::string& name) {
  return test::shipped_model(name);
}

Bytes le(std::int64_t v, std::size_t n) {
  Bytes out;
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i)));
  }
  return out;
}

/// Executes `instruction` in the protocol the servo speaks now, sent to its ID or to 0xFE.
ServoResponse run(Servo& servo, wire::Instruction instruction, bool broadcast = false) {
  const wire::InstructionPacket packet{servo.protocol().value_or(Protocol::V2),
                                       broadcast ? wire::kBroadcastId : servo.id(),
                                       std::move(instruction)};
  return servo.execute(packet,
                       broadcast ? model::Addressing::Broadcast : model::Addressing::Unicast);
}

/// Clear option 0x01 with its fixed bytes, or a reserved option (protocol2.md "Clear").
wire::Clear clear(std::uint8_t option) {
  return wire::Clear{option, {0x44, 0x58, 0x4C, 0x22}};
}

/// Control Table Backup: 0x01 store, 0x02 restore (protocol2.md "Control Table Backup").
wire::ControlTableBackup backup(std::uint8_t option) {
  return wire::ControlTableBackup{option, {0x43, 0x54, 0x52, 0x4C}};
}

wire::DecodeError decode_error(wire::DecodeErrorKind kind, std::uint8_t instruction) {
  return wire::DecodeError{kind, 1, instruction, "test"};
}

/// Status Return Level 0, 1 and 2 on one model: which of Ping, Read, Write and Reg Write are
/// answered, and whether the Write is applied anyway.
void check_status_return_levels(const std::string& name, std::uint16_t goal, std::size_t size) {
  for (std::int64_t level = 0; level <= 2; ++level) {
    CAPTURE(name, level);
    Servo servo(shipped(name), 1);
    servo.table().set("status_return_level", level);
    CHECK(run(servo, wire::Ping{}).replies);
    CHECK(run(servo, wire::Read{0, 2}).replies == (level >= 1));
    const std::int64_t target = 300 + level;
    CHECK(run(servo, wire::Write{goal, le(target, size)}).replies == (level == 2));
    CHECK(servo.table().get("goal_position") == target);  // applied even when not answered
    CHECK(run(servo, wire::RegWrite{goal, le(400, size)}).replies == (level == 2));
    // Broadcast Write: applied, never answered.
    CHECK_FALSE(run(servo, wire::Write{goal, le(500, size)}, true).replies);
    CHECK(servo.table().get("goal_position") == 500);
  }
}

}  // namespace

// ---- Ping ----

TEST_CASE("Ping answers model number LSB MSB and firmware version in 2.0", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  const ServoResponse r = run(servo, wire::Ping{});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.params == Bytes{0xFC, 0x03, 45});  // 1020 = 0x03FC, firmware 45
  CHECK(r.params == Bytes{static_cast<std::uint8_t>(servo.spec().model_number & 0xFF),
                          static_cast<std::uint8_t>(servo.spec().model_number >> 8),
                          servo.spec().firmware_version});
  CHECK(r.processing == microseconds(servo.spec().timing.ping_us));
  CHECK(r.processing == microseconds(50));
  CHECK_FALSE(r.reboot_after);
}

TEST_CASE("Ping in 1.0 is answered with no parameters", "[model][servo]") {
  Servo servo(shipped("ax-12a"), 1);
  const ServoResponse r = run(servo, wire::Ping{});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.params.empty());
  CHECK(r.processing == microseconds(18));  // ax-12a ping_us
}

TEST_CASE("Ping is answered at Status Return Level 0 and when broadcast", "[model][servo]") {
  for (const std::string name : {"xm430-w350", "ax-12a"}) {
    CAPTURE(name);
    Servo servo(shipped(name), 3);
    servo.table().set("status_return_level", 0);
    CHECK(run(servo, wire::Ping{}).replies);
    const ServoResponse broadcast = run(servo, wire::Ping{}, true);
    CHECK(broadcast.replies);
    CHECK(broadcast.error == 0x00);
  }
  Servo servo(shipped("xl-320"), 1);
  const ServoResponse r = run(servo, wire::Ping{}, true);
  CHECK(r.replies);
  CHECK(r.params == Bytes{0x5E, 0x01, 1});  // XL-320: 350 = 0x015E, firmware 1
}

// ---- Read ----

TEST_CASE("Read returns the bytes asked for with error 0", "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse r = run(x, wire::Read{0, 2});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.params == Bytes{0xFC, 0x03});
  CHECK(r.processing == microseconds(x.spec().timing.read_us));
  x.table().set("present_position", 166);
  CHECK(run(x, wire::Read{132, 4}).params == Bytes{0xA6, 0x00, 0x00, 0x00});

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse v1 = run(ax, wire::Read{0, 3});
  CHECK(v1.error == 0x00);
  CHECK(v1.params == Bytes{12, 0, 1});  // Model Number 12, Firmware Version 1
  CHECK(v1.processing == microseconds(22));
}

TEST_CASE("Read past the end is an Access Error in 2.0 and a Range Error in 1.0, with no data",
          "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse v2 = run(x, wire::Read{660, 4});  // the table ends at 661
  CHECK(v2.replies);
  CHECK(v2.error == 0x07);
  CHECK(v2.params.empty());

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse v1 = run(ax, wire::Read{48, 4});  // Punch (48, 49) is the last item
  CHECK(v1.replies);
  CHECK(v1.error == 0x08);
  CHECK(v1.params.empty());
}

TEST_CASE("Broadcast Read is not executed and not answered", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  const ServoResponse broadcast = run(servo, wire::Read{0, 2}, true);
  CHECK_FALSE(broadcast.replies);
  CHECK(broadcast.params.empty());
  REQUIRE(run(servo, wire::Read{0, 2}).replies);  // a unicast Read is
}

// ---- Write ----

TEST_CASE("Write is applied and answered with error 0", "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse r = run(x, wire::Write{116, le(512, 4)});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.params.empty());
  CHECK(x.table().get("goal_position") == 512);
  CHECK(r.processing == microseconds(50));

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse two = run(ax, wire::Write{30, le(300, 2)});
  CHECK(two.error == 0x00);
  CHECK(ax.table().get("goal_position") == 300);
  CHECK(two.processing == microseconds(24 + 6 * 2));
  CHECK(run(ax, wire::Write{25, {1}}).processing == microseconds(24 + 6));
}

TEST_CASE("Refused 2.0 Writes answer Access, Data Length, Data Range and Data Limit errors",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  CHECK(run(servo, wire::Write{0, le(1, 2)}).error == 0x07);        // Model Number is read-only
  CHECK(run(servo, wire::Write{116, le(100, 2)}).error == 0x05);    // half of Goal Position
  CHECK(run(servo, wire::Write{7, {253}}).error == 0x04);           // ID 0 ~ 252
  REQUIRE(run(servo, wire::Write{48, le(3000, 4)}).error == 0x00);  // Max Position Limit
  const ServoResponse limit = run(servo, wire::Write{116, le(3001, 4)});
  CHECK(limit.replies);
  CHECK(limit.error == 0x06);
  CHECK(servo.table().get("goal_position") == 2048);
  REQUIRE(run(servo, wire::Write{64, {1}}).error == 0x00);  // torque on locks EEPROM
  CHECK(run(servo, wire::Write{9, {0}}).error == 0x07);
  CHECK(servo.table().get("return_delay_time") == 250);
}

TEST_CASE("Refused 1.0 Writes answer the Range Error bit or the Angle Limit Error bit",
          "[model][servo]") {
  Servo servo(shipped("ax-12a"), 1);
  const ServoResponse range = run(servo, wire::Write{30, le(1024, 2)});
  CHECK(range.replies);
  CHECK(range.error == 0x08);
  REQUIRE(run(servo, wire::Write{6, le(200, 2)}).error == 0x00);  // CW Angle Limit
  REQUIRE(run(servo, wire::Write{8, le(800, 2)}).error == 0x00);  // CCW Angle Limit
  CHECK(run(servo, wire::Write{30, le(801, 2)}).error == 0x02);
  CHECK(servo.table().get("goal_position") == 512);
}

// ---- Status Return Level ----

TEST_CASE("Status Return Level 0 answers Ping only, 1 Ping and Read, 2 everything, in 2.0",
          "[model][servo]") {
  check_status_return_levels("xm430-w350", 116, 4);
}

TEST_CASE("Status Return Level 0 answers Ping only, 1 Ping and Read, 2 everything, in 1.0",
          "[model][servo]") {
  check_status_return_levels("ax-12a", 30, 2);
}

// includes/control_table_status_return_lv.md: "The Status Return Level decides how to return
// Status Packet when DYNAMIXEL receives an Instruction Packet": the level in force on arrival
// decides, not the one the instruction itself sets (a Write of the level, a Factory Reset).
TEST_CASE("The Status Return Level in force on arrival decides the reply, not the one set",
          "[model][servo]") {
  for (const std::string name : {"xm430-w350", "ax-12a"}) {
    CAPTURE(name);
    Servo servo(shipped(name), 1);
    servo.table().set("status_return_level", 0);
    const ServoResponse r = run(servo, wire::FactoryReset{});
    CHECK(r.reboot_after);
    CHECK(servo.table().get("status_return_level") == 2);  // executed
    CHECK_FALSE(r.replies);
  }
  Servo servo(shipped("xm430-w350"), 1);
  const ServoResponse lower = run(servo, wire::Write{68, {0}});
  CHECK(lower.replies);
  CHECK(servo.table().get("status_return_level") == 0);
  const ServoResponse raise = run(servo, wire::Write{68, {2}});
  CHECK_FALSE(raise.replies);
  CHECK(servo.table().get("status_return_level") == 2);
}

// ---- Reg Write and Action ----

TEST_CASE("Reg Write is held until Action, which applies it and clears Registered Instruction",
          "[model][servo]") {
  struct Case {
    const char* model;
    const char* flag;
    std::uint16_t goal;
    std::size_t size;
    std::uint8_t instruction_error;
  };
  for (const Case c : {Case{"xm430-w350", "registered_instruction", 116, 4, 0x02},
                       Case{"ax-12a", "registered", 30, 2, 0x40}}) {
    CAPTURE(c.model);
    Servo servo(shipped(c.model), 1);
    const std::int64_t initial = servo.table().get("goal_position");
    const ServoResponse reg = run(servo, wire::RegWrite{c.goal, le(1000, c.size)});
    CHECK(reg.replies);
    CHECK(reg.error == 0x00);
    CHECK(servo.table().get(c.flag) == 1);
    CHECK(servo.table().get("goal_position") == initial);

    const ServoResponse action = run(servo, wire::Action{});
    CHECK(action.replies);
    CHECK(action.error == 0x00);
    CHECK(servo.table().get("goal_position") == 1000);
    CHECK(servo.table().get(c.flag) == 0);

    const ServoResponse again = run(servo, wire::Action{});
    CHECK(again.replies);
    CHECK(again.error == c.instruction_error);
  }
}

TEST_CASE("A Reg Write with a bad value is refused and registers nothing", "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  CHECK(run(x, wire::RegWrite{116, le(5000, 4)}).error == 0x04);  // Goal Position 0 ~ 4095
  CHECK(x.table().get("registered_instruction") == 0);
  CHECK(run(x, wire::Action{}).error == 0x02);
  CHECK(x.table().get("goal_position") == 2048);

  Servo ax(shipped("ax-12a"), 1);
  CHECK(run(ax, wire::RegWrite{30, le(1024, 2)}).error == 0x08);
  CHECK(ax.table().get("registered") == 0);
  CHECK(run(ax, wire::Action{}).error == 0x40);
  CHECK(ax.table().get("goal_position") == 512);
}

TEST_CASE("Broadcast Action applies the registered write without a reply", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(run(servo, wire::RegWrite{116, le(700, 4)}).error == 0x00);
  const ServoResponse action = run(servo, wire::Action{}, true);
  CHECK_FALSE(action.replies);
  CHECK(servo.table().get("goal_position") == 700);
  CHECK(servo.table().get("registered_instruction") == 0);
}

// ---- Factory Reset ----

TEST_CASE("Factory Reset 2.0 resets EEPROM according to its option and asks for a reboot",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 5);
  REQUIRE(run(servo, wire::Write{9, {0}}).error == 0x00);  // Return Delay Time
  REQUIRE(run(servo, wire::Write{8, {3}}).error == 0x00);  // Baud Rate
  auto reset = [&](std::uint8_t option) {
    const ServoResponse r = run(servo, wire::FactoryReset{option});
    CHECK(r.replies);
    CHECK(r.error == 0x00);
    CHECK(r.reboot_after);
    CHECK(servo.table().get("return_delay_time") == 250);
  };
  SECTION("0xFF resets everything, ID included") {
    reset(0xFF);
    CHECK(servo.table().get("id") == 1);
    CHECK(servo.table().get("baud_rate") == 1);
    servo.reboot();
    CHECK(servo.id() == 1);
  }
  SECTION("0x01 keeps the ID") {
    reset(0x01);
    CHECK(servo.table().get("id") == 5);
    CHECK(servo.table().get("baud_rate") == 1);
  }
  SECTION("0x02 keeps the ID and the Baud Rate") {
    reset(0x02);
    CHECK(servo.table().get("id") == 5);
    CHECK(servo.table().get("baud_rate") == 3);
  }
}

TEST_CASE("Broadcast Factory Reset 0xFF is not executed while 0x01 is, without a reply",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 5);
  REQUIRE(run(servo, wire::Write{9, {0}}).error == 0x00);
  const ServoResponse all = run(servo, wire::FactoryReset{0xFF}, true);
  CHECK_FALSE(all.replies);
  CHECK_FALSE(all.reboot_after);
  CHECK(servo.table().get("return_delay_time") == 0);
  CHECK(servo.table().get("id") == 5);

  const ServoResponse but_id = run(servo, wire::FactoryReset{0x01}, true);
  CHECK_FALSE(but_id.replies);
  CHECK(but_id.reboot_after);
  CHECK(servo.table().get("return_delay_time") == 250);
  CHECK(servo.table().get("id") == 5);
}

TEST_CASE("Factory Reset 1.0 resets a unicast servo and ignores a broadcast one",
          "[model][servo]") {
  Servo servo(shipped("ax-12a"), 5);
  REQUIRE(run(servo, wire::Write{5, {0}}).error == 0x00);  // Return Delay Time
  const ServoResponse broadcast = run(servo, wire::FactoryReset{}, true);
  CHECK_FALSE(broadcast.replies);
  CHECK_FALSE(broadcast.reboot_after);
  CHECK(servo.table().get("id") == 5);
  CHECK(servo.table().get("return_delay_time") == 0);

  const ServoResponse r = run(servo, wire::FactoryReset{});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.reboot_after);
  CHECK(servo.table().get("id") == 1);
  CHECK(servo.table().get("return_delay_time") == 250);
}

// ---- Reboot ----

TEST_CASE("Reboot is answered, then reboot puts RAM back and keeps EEPROM", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(run(servo, wire::Write{9, {10}}).error == 0x00);  // Return Delay Time 20 us
  REQUIRE(run(servo, wire::Write{65, {1}}).error == 0x00);  // LED
  REQUIRE(run(servo, wire::Write{116, le(1000, 4)}).error == 0x00);
  REQUIRE(run(servo, wire::Write{64, {1}}).error == 0x00);  // Torque Enable
  REQUIRE(run(servo, wire::RegWrite{116, le(3000, 4)}).error == 0x00);

  const ServoResponse r = run(servo, wire::Reboot{});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(r.reboot_after);
  CHECK(servo.table().get("led") == 1);  // nothing changes before the reboot itself

  servo.reboot();
  CHECK(servo.table().get("led") == 0);
  CHECK(servo.table().get("goal_position") == 2048);
  CHECK(servo.table().get("torque_enable") == 0);
  CHECK(servo.table().get("registered_instruction") == 0);
  CHECK(servo.table().get("return_delay_time") == 10);
  CHECK(servo.return_delay() == microseconds(20));
  CHECK(run(servo, wire::Action{}).error == 0x02);  // the Reg Write slot is empty
}

TEST_CASE("AX answers Reboot with Instruction Error while MX-28 accepts it", "[model][servo]") {
  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse refused = run(ax, wire::Reboot{});
  CHECK(refused.replies);
  CHECK(refused.error == 0x40);
  CHECK_FALSE(refused.reboot_after);

  Servo mx(shipped("mx-28"), 1);
  const ServoResponse accepted = run(mx, wire::Reboot{});
  CHECK(accepted.replies);
  CHECK(accepted.error == 0x00);
  CHECK(accepted.reboot_after);
}

// ---- Deferred identity ----

TEST_CASE("A new ID takes effect only at commit_deferred", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  const ServoResponse r = run(servo, wire::Write{7, {7}});
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(servo.table().get("id") == 7);
  CHECK(servo.id() == 1);
  servo.commit_deferred();
  CHECK(servo.id() == 7);
}

TEST_CASE("Baud Rate, Return Delay Time and Protocol Type take effect at commit_deferred",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(servo.baud_bps() == 57'600);
  REQUIRE(servo.return_delay() == microseconds(500));
  REQUIRE(servo.protocol() == Protocol::V2);
  REQUIRE(run(servo, wire::Write{8, {3}}).error == 0x00);
  REQUIRE(run(servo, wire::Write{9, {10}}).error == 0x00);
  REQUIRE(run(servo, wire::Write{13, {1}}).error == 0x00);
  CHECK(servo.baud_bps() == 57'600);
  CHECK(servo.return_delay() == microseconds(500));
  CHECK(servo.protocol() == Protocol::V2);
  servo.commit_deferred();
  CHECK(servo.baud_bps() == 1'000'000);
  CHECK(servo.return_delay() == microseconds(20));
  CHECK(servo.protocol() == Protocol::V1);
}

TEST_CASE("XC330 Protocol Type 20 leaves the DYNAMIXEL bus at commit_deferred", "[model][servo]") {
  Servo servo(shipped("xc330-t288"), 1);
  REQUIRE(run(servo, wire::Write{13, {20}}).error == 0x00);  // Experimental S.BUS
  CHECK(servo.protocol() == Protocol::V2);
  servo.commit_deferred();
  CHECK(servo.protocol() == std::nullopt);
}

// includes/control_table_protocolversion.md (xl330/xc330): "In case that a RC Protocol type
// (Experimental S.BUS, Experimental iBUS, RC-PWM) is set, DYNAMIXEL will switch to DYNAMIXEL
// Protocol 2.0 on condition that RC protocol is not detected during booting." The emulator has no
// RC input, so no RC protocol is ever detected at boot.
TEST_CASE("XC330 with an RC Protocol Type boots into Protocol 2.0 when no RC signal is detected",
          "[model][servo]") {
  Servo servo(shipped("xc330-t288"), 1);
  REQUIRE(run(servo, wire::Write{13, {20}}).error == 0x00);
  servo.commit_deferred();
  servo.reboot();
  CHECK(servo.protocol() == Protocol::V2);
}

TEST_CASE("AX-12A Baud Rate 1 is 1 Mbps and an unlisted value n is 2 Mbps over n plus 1",
          "[model][servo]") {
  Servo servo(shipped("ax-12a"), 1);
  CHECK(servo.baud_bps() == 1'000'000);
  REQUIRE(run(servo, wire::Write{4, {15}}).error == 0x00);
  CHECK(servo.baud_bps() == 1'000'000);
  servo.commit_deferred();
  CHECK(servo.baud_bps() == 125'000);
  REQUIRE(run(servo, wire::Write{4, {34}}).error == 0x00);
  servo.commit_deferred();
  CHECK(servo.baud_bps() == 57'600);
}

// ---- Alert ----

TEST_CASE("Hardware Error Status sets the Alert bit in every 2.0 status", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(run(servo, wire::Ping{}).error == 0x00);
  servo.table().set("hardware_error_status", 4);  // Overheating
  const ServoResponse ping = run(servo, wire::Ping{});
  CHECK(ping.error == 0x80);
  CHECK(ping.params == Bytes{0xFC, 0x03, 45});
  CHECK(run(servo, wire::Write{65, {1}}).error == 0x80);
  CHECK(run(servo, wire::Read{0, 2}).error == 0x80);
  CHECK(run(servo, wire::Write{7, {253}}).error == 0x84);
  CHECK(run(servo, wire::Action{}).error == 0x82);
  CHECK(run(servo, wire::UnknownInstruction{0x07, {}}).error == 0x82);
  CHECK(run(servo, clear(0x02)).error == 0x84);
  CHECK(servo.read_part(0, 2).error == 0x80);
  CHECK(servo.refuse(decode_error(wire::DecodeErrorKind::BadLength, 0x03), false).error == 0x85);
}

// ---- Clear ----

TEST_CASE("Clear wraps Present Position into one turn when stopped", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  servo.table().set("present_position", 10000);
  const ServoResponse r = run(servo, clear(0x01));
  CHECK(r.replies);
  CHECK(r.error == 0x00);
  CHECK(servo.table().get("present_position") == 10000 % 4096);
  servo.table().set("present_position", -1);
  REQUIRE(run(servo, clear(0x01)).error == 0x00);
  CHECK(servo.table().get("present_position") == 4095);
}

TEST_CASE("Clear while moving answers Result Fail and changes nothing", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  servo.table().set("present_position", 10000);
  servo.table().set("moving", 1);
  const ServoResponse r = run(servo, clear(0x01));
  CHECK(r.replies);
  CHECK(r.error == 0x01);
  CHECK(servo.table().get("present_position") == 10000);
}

TEST_CASE("Clear with a reserved option answers Data Range Error", "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  servo.table().set("present_position", 10000);
  CHECK(run(servo, clear(0x02)).error == 0x04);
  CHECK(servo.table().get("present_position") == 10000);
}

// ---- Control Table Backup ----

TEST_CASE("Control Table Backup needs torque off and a stored backup to restore",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  servo.table().set("torque_enable", 1);
  const ServoResponse torque_on = run(servo, backup(0x01));
  CHECK(torque_on.replies);
  CHECK(torque_on.error == 0x01);
  CHECK_FALSE(servo.has_backup());
  CHECK(servo.table().get("backup_ready") == 0);

  servo.table().set("torque_enable", 0);
  const ServoResponse nothing_stored = run(servo, backup(0x02));
  CHECK(nothing_stored.error == 0x01);
  CHECK_FALSE(nothing_stored.reboot_after);

  const ServoResponse store = run(servo, backup(0x01));
  CHECK(store.replies);
  CHECK(store.error == 0x00);
  CHECK_FALSE(store.reboot_after);
  CHECK(servo.has_backup());
  CHECK(servo.table().get("backup_ready") == 1);
}

TEST_CASE("Control Table Backup restore brings EEPROM back and asks for a reboot",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(run(servo, backup(0x01)).error == 0x00);
  REQUIRE(run(servo, wire::Write{9, {0}}).error == 0x00);  // Return Delay Time
  const ServoResponse restore = run(servo, backup(0x02));
  CHECK(restore.replies);
  CHECK(restore.error == 0x00);
  CHECK(restore.reboot_after);
  CHECK(servo.table().get("return_delay_time") == 250);
  servo.reboot();
  CHECK(servo.return_delay() == microseconds(500));
  CHECK(servo.table().get("backup_ready") == 1);  // Backup Ready survives the reboot
}

TEST_CASE("Startup Configuration restores backed-up RAM and turns torque on at reboot",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  REQUIRE(run(servo, wire::Write{84, le(1000, 2)}).error == 0x00);  // Position P Gain
  REQUIRE(run(servo, wire::Write{112, le(77, 4)}).error == 0x00);   // Profile Velocity
  REQUIRE(run(servo, wire::Write{168, le(132, 2)}).error == 0x00);  // Indirect Address 1
  REQUIRE(run(servo, wire::Write{65, {1}}).error == 0x00);          // LED: not backed up
  REQUIRE(run(servo, backup(0x01)).error == 0x00);
  SECTION("bit 1 restores the RAM items of the backup") {
    REQUIRE(run(servo, wire::Write{60, {0x02}}).error == 0x00);
    servo.reboot();
    CHECK(servo.table().get("position_p_gain") == 1000);
    CHECK(servo.table().get("profile_velocity") == 77);
    CHECK(servo.table().get("indirect_address_1") == 132);
    CHECK(servo.table().get("led") == 0);
    CHECK(servo.table().get("torque_enable") == 0);
  }
  SECTION("bit 0 turns torque on and restores no RAM") {
    REQUIRE(run(servo, wire::Write{60, {0x01}}).error == 0x00);
    servo.reboot();
    CHECK(servo.table().get("torque_enable") == 1);
    CHECK(servo.table().get("position_p_gain") == 800);
    CHECK(servo.table().get("profile_velocity") == 0);
  }
}

TEST_CASE("Models without Backup Ready answer Control Table Backup with Instruction Error",
          "[model][servo]") {
  for (const std::string name : {"h54-200-s500-r", "xl-320"}) {
    CAPTURE(name);
    Servo servo(shipped(name), 1);
    const ServoResponse r = run(servo, backup(0x01));
    CHECK(r.replies);
    CHECK(r.error == 0x02);
    CHECK_FALSE(servo.has_backup());
  }
}

// ---- Unknown instructions and undecodable packets ----

TEST_CASE("An unknown instruction answers Instruction Error, silently when broadcast",
          "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse v2 = run(x, wire::UnknownInstruction{0x07, {}});
  CHECK(v2.replies);
  CHECK(v2.error == 0x02);
  CHECK_FALSE(run(x, wire::UnknownInstruction{0x07, {}}, true).replies);

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse v1 = run(ax, wire::UnknownInstruction{0x07, {}});
  CHECK(v1.replies);
  CHECK(v1.error == 0x40);
  CHECK_FALSE(run(ax, wire::UnknownInstruction{0x07, {}}, true).replies);
}

TEST_CASE("Undecodable parameters are refused with the error of the servo protocol",
          "[model][servo]") {
  using wire::DecodeErrorKind;
  const auto bad_length = decode_error(DecodeErrorKind::BadLength, 0x03);
  const auto bad_value = decode_error(DecodeErrorKind::BadValue, 0x06);

  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse length = x.refuse(bad_length, false);
  CHECK(length.replies);
  CHECK(length.error == 0x05);
  CHECK(length.params.empty());
  CHECK(x.refuse(bad_value, false).error == 0x04);
  CHECK_FALSE(x.refuse(bad_length, true).replies);
  x.table().set("status_return_level", 1);
  CHECK_FALSE(x.refuse(bad_length, false).replies);  // a Write is not answered at level 1
  CHECK(x.refuse(decode_error(DecodeErrorKind::BadLength, 0x02), false).replies);  // a Read is

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse v1 = ax.refuse(bad_length, false);
  CHECK(v1.replies);
  CHECK(v1.error == 0x40);
  CHECK(ax.refuse(bad_value, false).error == 0x08);
  CHECK_FALSE(ax.refuse(bad_value, true).replies);
}

// ---- Sync/Bulk parts ----

TEST_CASE("read_part returns the data or an error with no data", "[model][servo]") {
  Servo x(shipped("xm430-w350"), 1);
  const ServoResponse data = x.read_part(0, 2);
  CHECK(data.replies);
  CHECK(data.error == 0x00);
  CHECK(data.params == Bytes{0xFC, 0x03});
  const ServoResponse past_end = x.read_part(660, 4);
  CHECK(past_end.error == 0x07);
  CHECK(past_end.params.empty());

  Servo ax(shipped("ax-12a"), 1);
  const ServoResponse v1 = ax.read_part(48, 4);
  CHECK(v1.error == 0x08);
  CHECK(v1.params.empty());
}

TEST_CASE("write_part applies a write like Write and refuses what Write refuses",
          "[model][servo]") {
  Servo servo(shipped("xm430-w350"), 1);
  servo.write_part(116, le(700, 4));
  CHECK(servo.table().get("goal_position") == 700);
  servo.write_part(116, le(5000, 4));  // out of range: nothing changes
  CHECK(servo.table().get("goal_position") == 700);
  servo.write_part(0, le(1, 2));  // read-only
  CHECK(servo.table().get("model_number") == 1020);
}
