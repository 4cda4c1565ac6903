// A DYNAMIXEL-P servo speaking Modbus RTU on the bus: the register map on its control table,
// exceptions, the switch between Protocol 2.0 and Modbus, and reply timing on the virtual clock
// (docs/modbus.md).
#include <catch2/catch.hpp>

#include "bus_rig.hpp"
#include "wire/hex.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/rtu_timing.hpp"

namespace dxlemu::test::modbus_bus {

using namespace std::chrono_literals;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

Bytes hex(std::string_view text) {
  return wire::parse_hex(text).value();
}

/// t3.5 at the rig's 57,600 bit/s: the fixed 1,750 us.
constexpr sim::SimDuration kSilence = 1750us;
/// PH54-200-S500-R: 50 us to process; no Return Delay Time over Modbus.
constexpr sim::SimDuration kProcessing = 50us;

/// A PH54-200-S500-R at ID 1 speaking Modbus RTU (Protocol Type 10), on a rig.
struct ModbusRig : BusRig {
  model::Servo& servo;
  ModbusRig() : servo(add("ph54-200-s500-r", 1)) {
    servo.table().set("protocol_type", wire::traits(Protocol::Modbus).type_value);
    servo.commit_deferred();
  }
  /// The client writes `frame` now; returns the reply bytes of the one delivery that followed
  /// (empty when none), and checks its time when `check_time`.
  Bytes ask(const Bytes& frame) {
    const std::size_t before = link.deliveries().size();
    bus.receive(frame, scheduler.now(), kBaud);
    run();
    if (link.deliveries().size() == before) {
      return {};
    }
    REQUIRE(link.deliveries().size() == before + 1);
    return link.deliveries().back().bytes;
  }
  Bytes ask(std::uint8_t function, const Bytes& data, std::uint8_t address = 1) {
    return ask(wire::encode_modbus_frame(address, function, data));
  }
};

TEST_CASE("Model Number 2020 is at 40001, answered t3.5 after the request plus processing",
          "[bus][modbus]") {
  ModbusRig rig;
  REQUIRE(rig.servo.protocol() == Protocol::Modbus);
  const Bytes request = hex("01 03 00 00 00 02 C4 0B");
  const Bytes reply = rig.ask(request);
  // Model Number 2020 = 0x07E4, Model Information 0.
  CHECK(reply == wire::encode_modbus_frame(1, 0x03, hex("04 07 E4 00 00")));
  const auto& d = rig.link.deliveries().back();
  CHECK(d.at ==
        sim::SimTime{} + line(request.size()) + kSilence + kProcessing + line(reply.size()));
}

TEST_CASE("Torque Enable and Goal Position written over Modbus move the servo",
          "[bus][modbus][motion]") {
  ModbusRig rig;
  CHECK(rig.ask(hex("01 06 01 00 00 01 49 F6")) == hex("01 06 01 00 00 01 49 F6"));
  CHECK(rig.servo.table().get("torque_enable") == 1);
  // Goal Position = 20000 pulses: registers 0x4E20, 0x0000 (low word first).
  CHECK(rig.ask(0x10, hex("01 1A 00 02 04 4E 20 00 00")) ==
        wire::encode_modbus_frame(1, 0x10, hex("01 1A 00 02")));
  CHECK(rig.servo.table().get("goal_position") == 20000);
  rig.run(3s);
  const Bytes present = rig.ask(0x03, hex("01 22 00 02"));
  REQUIRE(present.size() == 9);
  const std::int64_t position =
      (present[3] << 8 | present[4]) | (present[5] << 24 | present[6] << 16);
  CHECK(position == rig.servo.table().get("present_position"));
  CHECK(std::abs(position - 20000) < 200);
}

TEST_CASE("Modbus exceptions: read-only 02, part of an item 02, out of range 03, locked 04",
          "[bus][modbus]") {
  ModbusRig rig;
  // Model Number is read-only: no byte of register 0 can be written.
  CHECK(rig.ask(0x06, hex("00 00 00 05")) == hex("01 86 02 C3 A1"));
  // Present Position (580) likewise.
  CHECK(rig.ask(0x10, hex("01 22 00 02 04 00 00 00 00")) ==
        wire::encode_modbus_frame(1, 0x90, hex("02")));
  // One register of the 4-byte Goal Position.
  CHECK(rig.ask(0x06, hex("01 1A 00 10")) == wire::encode_modbus_frame(1, 0x86, hex("02")));
  // Operating Mode 2 is not among 0, 1, 3, 4, 16 (register 40006, high byte).
  CHECK(rig.ask(0x06, hex("00 05 02 00")) == wire::encode_modbus_frame(1, 0x86, hex("03")));
  // EEPROM while the torque is on.
  rig.ask(hex("01 06 01 00 00 01 49 F6"));
  CHECK(rig.ask(0x06, hex("00 05 04 00")) == wire::encode_modbus_frame(1, 0x86, hex("04")));
  // A function it does not serve, and a quantity out of range.
  CHECK(rig.ask(0x01, hex("00 00 00 01")) == wire::encode_modbus_frame(1, 0x81, hex("01")));
  CHECK(rig.ask(0x03, hex("00 00 00 7E")) == wire::encode_modbus_frame(1, 0x83, hex("03")));
  // Past the end of the table.
  CHECK(rig.ask(0x03, hex("7F 00 00 01")) == wire::encode_modbus_frame(1, 0x83, hex("02")));
  // Diagnostics: Return Query Data echoes.
  CHECK(rig.ask(0x08, hex("00 00 12 34")) ==
        wire::encode_modbus_frame(1, 0x08, hex("00 00 12 34")));
}

TEST_CASE("Items the page prints N/A refuse, and a register half N/A serves its other byte",
          "[bus][modbus]") {
  ModbusRig rig;
  // 40259 holds Status Return Level (516) and Registered Instruction (517): both N/A.
  CHECK(rig.ask(0x03, hex("01 02 00 01")) == wire::encode_modbus_frame(1, 0x83, hex("02")));
  CHECK(rig.ask(0x06, hex("01 02 00 00")) == wire::encode_modbus_frame(1, 0x86, hex("02")));
  // Indirect Address 1 (168) is N/A.
  CHECK(rig.ask(0x03, hex("00 54 00 01")) == wire::encode_modbus_frame(1, 0x83, hex("02")));
  // 40005: Baud Rate (8) low byte, Return Delay Time (9, N/A, 250) high byte reads 0.
  CHECK(rig.ask(0x03, hex("00 04 00 01")) == wire::encode_modbus_frame(1, 0x03, hex("02 00 01")));
  // A write of 40005 sets Baud Rate and leaves Return Delay Time alone.
  CHECK(!rig.ask(0x06, hex("00 04 07 03")).empty());
  CHECK(rig.servo.table().get("baud_rate") == 3);
  CHECK(rig.servo.table().get("return_delay_time") == 250);
}

TEST_CASE("The ID is written through 40004's high byte, 1 ~ 247, after the response",
          "[bus][modbus]") {
  ModbusRig rig;
  // Firmware Version (6, read-only) is the low byte: its value is ignored.
  CHECK(rig.ask(0x06, hex("00 03 F8 00")) == wire::encode_modbus_frame(1, 0x86, hex("03")));
  CHECK(rig.ask(0x06, hex("00 03 05 FF")) ==
        wire::encode_modbus_frame(1, 0x06, hex("00 03 05 FF")));
  CHECK(rig.servo.id() == 5);
  CHECK(rig.ask(0x03, hex("00 00 00 01")).empty());  // nobody at 1 now
  CHECK(rig.ask(0x03, hex("00 00 00 01"), 5) ==
        wire::encode_modbus_frame(5, 0x03, hex("02 07 E4")));
}

TEST_CASE("Broadcast, other addresses and bad CRCs are never answered", "[bus][modbus]") {
  ModbusRig rig;
  // Address 0: the write is executed by every server and never answered.
  CHECK(rig.ask(0x06, hex("01 00 00 01"), 0).empty());
  CHECK(rig.servo.table().get("torque_enable") == 1);
  CHECK(rig.ask(0x03, hex("00 00 00 01"), 0).empty());  // a broadcast read is not executed
  CHECK(rig.ask(0x03, hex("00 00 00 01"), 2).empty());
  Bytes damaged = hex("01 03 00 00 00 02 C4 0B");
  damaged[7] ^= 0xFF;
  CHECK(rig.ask(damaged).empty());
  CHECK(rig.bus.stats().bad_checks == 1);
}

TEST_CASE("Protocol Type 10 over 2.0 switches to Modbus after its status, 2 over Modbus back",
          "[bus][modbus]") {
  BusRig rig;
  model::Servo& servo = rig.add("ph54-200-s500-r", 1);
  rig.send({Protocol::V2, 1, wire::Write{13, {10}}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=1 error=0x00");
  CHECK(servo.protocol() == Protocol::Modbus);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);  // a 2.0 Ping is noise to it now
  // 40007's high byte is Protocol Type (13); its low byte Secondary ID (12) is N/A.
  rig.bus.receive(wire::encode_modbus_frame(1, 0x06, hex("00 06 02 00")), rig.scheduler.now(),
                  BusRig::kBaud);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 2);
  CHECK(rig.link.deliveries()[1].bytes == wire::encode_modbus_frame(1, 0x06, hex("00 06 02 00")));
  CHECK(servo.protocol() == Protocol::V2);
  CHECK(servo.table().get("secondary_id") == 255);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 3);
  CHECK(test::status_text(rig.link.deliveries()[2].bytes) == "id=1 error=0x00 params=E4 07 2D");
}

TEST_CASE("Without modelled delays a Modbus frame ends with the client's write",
          "[bus][modbus][timing]") {
  ModbusRig rig;
  rig.bus.set_reply_timing(bus::ReplyTiming::Immediate);
  rig.bus.receive(hex("01 03 00 00 00 02 C4 0B"), rig.scheduler.now(), BusRig::kBaud);
  rig.scheduler.advance_by(0ns);
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].at == sim::SimTime{});
}

TEST_CASE("A Modbus frame split by a gap over t1.5 is discarded, silently", "[bus][modbus]") {
  ModbusRig rig;
  const Bytes request = hex("01 03 00 00 00 02 C4 0B");
  rig.bus.receive(Bytes(request.begin(), request.begin() + 4), rig.scheduler.now(), BusRig::kBaud);
  rig.scheduler.advance_by(line(4) + 800us);
  rig.bus.receive(Bytes(request.begin() + 4, request.end()), rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.stats().truncated == 1);
}

}  // namespace dxlemu::test::modbus_bus
