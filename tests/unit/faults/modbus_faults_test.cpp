// Fault rules on a Modbus RTU port (docs/faults.md "Modbus RTU"): matching by function name and
// by control-table address, the modbus_exception action, and the reply actions on Modbus
// responses, on the virtual clock.
#include <catch2/catch.hpp>

#include "bus/bus_rig.hpp"
#include "faults/injector.hpp"
#include "faults/port_faults.hpp"
#include "faults/rule_parser.hpp"
#include "wire/crc16_modbus.hpp"
#include "wire/hex.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/rtu_timing.hpp"

namespace dxlemu::test::modbus_faults {

using namespace std::chrono_literals;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

Bytes hex(std::string_view text) {
  return wire::parse_hex(text).value();
}

/// A PH54-200-S500-R at ID 1 speaking Modbus RTU (or, with `protocol` 2.0, speaking 2.0) on
/// port "dxl0" with an injector of seed 1.
struct ModbusFaultRig {
  faults::Injector injector{1};
  BusRig rig;
  faults::PortFaults faults{rig.scheduler, rig.bus.servos()};
  model::Servo& modbus;

  explicit ModbusFaultRig(Protocol protocol = Protocol::Modbus)
      : modbus(rig.add("ph54-200-s500-r", 1)) {
    modbus.table().set("protocol_type", wire::traits(protocol).type_value);
    modbus.commit_deferred();
    faults.set_rules(&injector, "dxl0");
    rig.bus.set_faults(&faults);
  }
  std::uint64_t add(const std::string& rule) {
    return injector.add(faults::parse_rule(nlohmann::json::parse(rule)), rig.scheduler.now());
  }
  /// The client writes `frame` now; returns what reached it in the second after (empty: none).
  std::vector<bus::LoopbackLink::Delivery> exchange(const Bytes& frame) {
    rig.link.clear();
    rig.bus.receive(frame, rig.scheduler.now(), BusRig::kBaud);
    rig.run();
    auto out = rig.link.deliveries();
    rig.link.clear();
    return out;
  }
  /// The bytes of the one delivery `frame` brings, or empty.
  Bytes ask(const Bytes& frame) {
    const auto d = exchange(frame);
    REQUIRE(d.size() <= 1);
    return d.empty() ? Bytes{} : d.front().bytes;
  }
  Bytes ask(std::uint8_t function, const Bytes& data, std::uint8_t address = 1) {
    return ask(wire::encode_modbus_frame(address, function, data));
  }
};

// Read Holding Registers 40001 ~ 40002 (Model Number) of address 1, and its response.
const Bytes kReadModel = hex("01 03 00 00 00 02 C4 0B");

TEST_CASE("modbus_exception: the request is not executed and the servo answers the exception",
          "[faults][modbus]") {
  ModbusFaultRig f;
  const auto clean = f.exchange(hex("01 06 01 00 00 01 49 F6"));  // Torque Enable 1
  REQUIRE(clean.size() == 1);
  const sim::SimDuration clean_after = clean.front().at - (f.rig.scheduler.now() - 1s);
  f.modbus.table().set("torque_enable", 0);
  f.add(R"({"action":"modbus_exception","match":{"instruction":"write_single_register"}})");
  const sim::SimTime sent = f.rig.scheduler.now();
  const auto refused = f.exchange(hex("01 06 01 00 00 01 49 F6"));
  REQUIRE(refused.size() == 1);
  // Function 06 | 0x80, exception 06 (Server Device Busy, the default).
  CHECK(refused.front().bytes == wire::encode_modbus_frame(1, 0x86, hex("06")));
  CHECK(f.modbus.table().get("torque_enable") == 0);
  // At the time a reply of its size would have come: the same processing time (50 us on a P).
  const sim::SimDuration reply_gap =
      test::line(clean.front().bytes.size()) - test::line(refused.front().bytes.size());
  CHECK(refused.front().at - sent == clean_after - reply_gap);
  // Other functions pass.
  CHECK(f.ask(kReadModel) == wire::encode_modbus_frame(1, 0x03, hex("04 07 E4 00 00")));
  CHECK(f.rig.bus.stats().faults_injected == 1);
}

TEST_CASE("modbus_exception takes its code and counts, and a broadcast gets no answer",
          "[faults][modbus]") {
  ModbusFaultRig f;
  f.add(R"({"action":"modbus_exception","code":4,"count":1})");
  CHECK(f.ask(kReadModel) == wire::encode_modbus_frame(1, 0x83, hex("04")));
  CHECK(f.ask(kReadModel) == wire::encode_modbus_frame(1, 0x03, hex("04 07 E4 00 00")));
  f.add(R"({"action":"modbus_exception","code":255})");
  // Broadcast (address 0): not executed, and, broadcast, not answered.
  CHECK(f.ask(0x06, hex("01 00 00 01"), 0).empty());
  CHECK(f.modbus.table().get("torque_enable") == 0);
  CHECK(f.ask(0x08, hex("00 00 AB CD")) == wire::encode_modbus_frame(1, 0x88, hex("FF")));
}

TEST_CASE("modbus_exception never matches a packet of another protocol", "[faults][modbus]") {
  ModbusFaultRig f(Protocol::V2);
  const std::uint64_t id = f.add(R"({"action":"modbus_exception"})");
  const auto d = f.exchange(wire::encode_instruction({Protocol::V2, 1, wire::Read{0, 2}}));
  REQUIRE(d.size() == 1);
  CHECK_THAT(test::status_text(d.front().bytes), Catch::StartsWith("id=1 error=0x00"));
  // Not even counted as a match: the rule has no Modbus request to refuse there.
  CHECK(f.injector.rules().front().id == id);
  CHECK(f.injector.rules().front().matched == 0);
  CHECK(f.rig.bus.stats().faults_injected == 0);
}

TEST_CASE("Rules match Modbus requests by function name and control-table byte address",
          "[faults][modbus]") {
  ModbusFaultRig f;
  // Goal Position is bytes 564 ~ 567 of a PH54: registers 282 ~ 283 (0x011A).
  f.add(R"({"action":"drop_reply","match":{"address":[564,567]}})");
  CHECK(f.ask(kReadModel).size() == 9);
  CHECK(f.ask(0x03, hex("01 1A 00 02")).empty());      // reads 564 ~ 567
  CHECK(f.ask(0x03, hex("01 1B 00 01")).empty());      // reads 566 ~ 567
  CHECK(f.ask(0x03, hex("01 1C 00 01")).size() == 7);  // reads 568 ~ 569
  // A write of Goal Position is executed; only its reply is dropped.
  CHECK(f.ask(0x10, hex("01 1A 00 02 04 00 64 00 00")).empty());
  CHECK(f.modbus.table().get("goal_position") == 100);
  // The function names of the Modbus row.
  f.injector.clear();
  f.add(R"({"action":"drop_reply","match":{"instruction":["read_holding_registers"]}})");
  CHECK(f.ask(kReadModel).empty());
  CHECK(f.ask(0x04, hex("00 00 00 02")).size() == 9);  // read_input_registers
  f.injector.clear();
  f.add(R"({"action":"drop_reply","match":{"instruction":"diagnostics"}})");
  CHECK(f.ask(0x08, hex("00 00 12 34")).empty());
  CHECK(f.ask(kReadModel).size() == 9);
}

TEST_CASE("Reply faults damage Modbus responses: CRC, address, truncation, delay",
          "[faults][modbus]") {
  const Bytes good = wire::encode_modbus_frame(1, 0x03, hex("04 07 E4 00 00"));
  {
    ModbusFaultRig f;
    f.add(R"({"action":"corrupt_crc"})");
    const Bytes bytes = f.ask(kReadModel);
    REQUIRE(bytes.size() == good.size());
    CHECK(std::equal(bytes.begin(), bytes.end() - 1, good.begin()));
    CHECK(wire::crc16_modbus(std::span(bytes).first(bytes.size() - 2)) !=
          (bytes[bytes.size() - 2] | bytes.back() << 8));
  }
  {
    ModbusFaultRig f;
    f.add(R"({"action":"wrong_id","id":9})");
    // A valid response from address 9.
    CHECK(f.ask(kReadModel) == wire::encode_modbus_frame(9, 0x03, hex("04 07 E4 00 00")));
  }
  {
    ModbusFaultRig f;
    f.add(R"({"action":"truncate_reply","bytes":3})");
    CHECK(f.ask(kReadModel) == Bytes(good.begin(), good.begin() + 3));
  }
  {
    ModbusFaultRig clean;
    const auto before = clean.exchange(kReadModel);
    ModbusFaultRig f;
    f.add(R"({"action":"delay_reply","us":2000})");
    const auto after = f.exchange(kReadModel);
    REQUIRE(before.size() == 1);
    REQUIRE(after.size() == 1);
    CHECK(after.front().at - before.front().at == 2000us);
  }
}

TEST_CASE("A Diagnostics request does not wake a servo silent until a reboot", "[faults][modbus]") {
  // 0x08 is Reboot in DYNAMIXEL and Diagnostics in Modbus RTU: only a Reboot ends the silence.
  ModbusFaultRig f;
  f.add(R"({"action":"silence_until_reboot","count":1})");
  CHECK(f.ask(kReadModel).empty());
  CHECK(f.ask(0x08, hex("00 00 12 34")).empty());
  CHECK(f.ask(kReadModel).empty());
  f.rig.bus.power_on(f.modbus);
  f.rig.run();
  CHECK(f.ask(kReadModel).size() == 9);
}

}  // namespace dxlemu::test::modbus_faults
