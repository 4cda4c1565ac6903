// Every fault action on a real bus (docs/faults.md): what reaches the client, when, and what the
// servos do, on the virtual clock.
#include <bit>
#include <catch2/catch.hpp>

#include "bus/bus_rig.hpp"
#include "faults/injector.hpp"
#include "faults/port_faults.hpp"
#include "faults/rule_parser.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using test::BusRig;
using test::kBroadcast;
using test::status_text;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

/// XM430-W350 servos 1, 2 and 3 on port "dxl0", with an injector of seed 1.
struct FaultRig {
  faults::Injector injector{1};
  BusRig rig;
  faults::PortFaults faults{rig.scheduler, rig.bus.servos()};

  FaultRig() {
    for (std::uint8_t id = 1; id <= 3; ++id) {
      rig.add("xm430-w350", id);
    }
    faults.set_rules(&injector, "dxl0");
    rig.bus.set_faults(&faults);
  }
  /// Adds the rule written as JSON (the bus follows it at once).
  std::uint64_t add(const std::string& rule) {
    return injector.add(faults::parse_rule(nlohmann::json::parse(rule)), rig.scheduler.now());
  }
  /// Sends `packet`, lets a second pass, and returns what reached the client (then forgets it).
  std::vector<bus::LoopbackLink::Delivery> exchange(const wire::InstructionPacket& packet) {
    rig.link.clear();
    rig.send(packet);
    rig.run();
    auto out = rig.link.deliveries();
    rig.link.clear();
    return out;
  }
  model::Servo& servo(std::size_t i) const { return *rig.bus.servos()[i]; }
};

const wire::InstructionPacket kPing1{Protocol::V2, 1, wire::Ping{}};

/// The one delivery of a fault-free Ping of servo 1: bytes and time after the instruction.
bus::LoopbackLink::Delivery clean_ping() {
  FaultRig clean;
  auto d = clean.exchange(kPing1);
  REQUIRE(d.size() == 1);
  return d.front();
}

}  // namespace

TEST_CASE("drop_reply: the status never arrives, and count 1 drops only the first",
          "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"drop_reply","match":{"servos":[1]},"count":1})");
  CHECK(f.exchange(kPing1).empty());
  CHECK(f.rig.bus.stats().faults_injected == 1);
  CHECK(f.exchange(kPing1).size() == 1);
  CHECK(f.exchange({Protocol::V2, 2, wire::Ping{}}).size() == 1);
}

TEST_CASE("delay_reply and slow: the status arrives that much later", "[faults][bus]") {
  const auto clean = clean_ping();
  for (const char* rule :
       {R"({"action":"delay_reply","us":2000})", R"({"action":"slow","us":2000})"}) {
    INFO(rule);
    FaultRig f;
    f.add(rule);
    const auto d = f.exchange(kPing1);
    REQUIRE(d.size() == 1);
    CHECK(d.front().bytes == clean.bytes);
    CHECK(d.front().at == clean.at + 2ms);
  }
}

TEST_CASE("A delayed status delays the chain of a Sync Read after it", "[faults][bus]") {
  FaultRig clean;
  const auto before = clean.exchange({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {1, 2, 3}}});
  FaultRig f;
  f.add(R"({"action":"delay_reply","us":1000,"match":{"servos":[2]}})");
  const auto after = f.exchange({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {1, 2, 3}}});
  REQUIRE(before.size() == 3);
  REQUIRE(after.size() == 3);
  CHECK(after[0].at == before[0].at);
  CHECK(after[1].at == before[1].at + 1ms);
  CHECK(after[2].at == before[2].at + 1ms);
}

TEST_CASE("corrupt_crc, flip_bits, truncate_reply, garbage_before, duplicate_reply, wrong_id",
          "[faults][bus]") {
  const auto clean = clean_ping();
  const Bytes& good = clean.bytes;
  const auto one = [](FaultRig& f) {
    auto d = f.exchange(kPing1);
    REQUIRE(d.size() == 1);
    return d.front().bytes;
  };
  {
    FaultRig f;
    f.add(R"({"action":"corrupt_crc"})");
    const Bytes got = one(f);
    CHECK(status_text(got) == "not one status packet");
    CHECK(Bytes(got.begin(), got.end() - 1) == Bytes(good.begin(), good.end() - 1));
  }
  {
    FaultRig f;
    f.add(R"({"action":"flip_bits","bits":2})");
    const Bytes got = one(f);
    REQUIRE(got.size() == good.size());
    int bits = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
      bits += std::popcount(static_cast<unsigned>(got[i] ^ good[i]));
    }
    CHECK(bits == 2);
  }
  {
    FaultRig f;
    f.add(R"({"action":"truncate_reply","bytes":5})");
    CHECK(one(f) == Bytes(good.begin(), good.begin() + 5));
  }
  {
    FaultRig f;
    f.add(R"({"action":"garbage_before","data":[1,2,3]})");
    Bytes expected{1, 2, 3};
    expected.reserve(expected.size() + good.size());
    expected.insert(expected.end(), good.begin(), good.end());
    CHECK(one(f) == expected);
  }
  {
    FaultRig f;
    f.add(R"({"action":"duplicate_reply"})");
    Bytes expected = good;
    expected.insert(expected.end(), good.begin(), good.end());
    CHECK(one(f) == expected);
  }
  {
    FaultRig f;
    f.add(R"({"action":"wrong_id","id":7})");
    CHECK(status_text(one(f)) == "id=7 error=0x00 params=FC 03 2D");
    f.injector.clear();
    f.add(R"({"action":"wrong_id"})");  // the ID above the servo's own
    CHECK(status_text(one(f)) == "id=2 error=0x00 params=FC 03 2D");
  }
}

TEST_CASE("echo_instruction and noise: extra bytes reach the client before the status",
          "[faults][bus]") {
  const auto clean = clean_ping();
  FaultRig f;
  f.add(R"({"action":"echo_instruction"})");
  f.add(R"({"action":"noise","bytes":6})");
  f.rig.link.clear();
  const std::size_t sent = f.rig.send(kPing1);
  f.rig.run();
  const auto d = f.rig.link.deliveries();
  REQUIRE(d.size() == 3);
  CHECK(d[0].bytes == wire::encode_instruction(kPing1));
  CHECK(d[0].at == sim::SimTime{} + test::line(sent));
  CHECK(d[1].bytes.size() == 6);
  CHECK(d[1].at == d[0].at);
  CHECK(d[2].bytes == clean.bytes);
  CHECK(d[2].at == clean.at);
  CHECK(f.rig.bus.stats().replies == 1);  // the echo and the noise are not status packets
}

TEST_CASE("corrupt_instruction: the servo hears a bad CRC, answers CRC Error and writes nothing",
          "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"corrupt_instruction","match":{"instruction":"write"}})");
  const auto d = f.exchange({Protocol::V2, 1, wire::Write{65, {1}}});  // LED on
  REQUIRE(d.size() == 1);
  CHECK(status_text(d.front().bytes) == "id=1 error=0x03");
  CHECK(f.servo(0).table().get("led") == 0);
  CHECK(f.exchange(kPing1).size() == 1);  // a Ping is not a Write: untouched
}

TEST_CASE(
    "hardware_error: the error latches, survives a Reboot while the rule lasts, and is gone "
    "after fault.remove and a Reboot",
    "[faults][bus]") {
  FaultRig f;
  const auto rule =
      f.add(R"({"action":"hardware_error","kind":"overheating","match":{"servos":[3]}})");
  f.rig.run(5ms);
  const wire::InstructionPacket ping3{Protocol::V2, 3, wire::Ping{}};
  const wire::InstructionPacket read_status{Protocol::V2, 3, wire::Read{70, 1}};
  CHECK(status_text(f.exchange(ping3).front().bytes) == "id=3 error=0x80 params=FC 03 2D");
  CHECK(status_text(f.exchange(read_status).front().bytes) == "id=3 error=0x80 params=04");
  CHECK(status_text(f.exchange(kPing1).front().bytes) == "id=1 error=0x00 params=FC 03 2D");

  f.exchange({Protocol::V2, 3, wire::Reboot{}});
  f.rig.run(5ms);
  CHECK(status_text(f.exchange(read_status).front().bytes) == "id=3 error=0x80 params=04");

  f.injector.remove(rule);
  CHECK(status_text(f.exchange(read_status).front().bytes) == "id=3 error=0x80 params=04");
  f.exchange({Protocol::V2, 3, wire::Reboot{}});
  f.rig.run(5ms);
  CHECK(status_text(f.exchange(read_status).front().bytes) == "id=3 error=0x00 params=00");
  // Torque Enable is accepted again.
  CHECK(status_text(f.exchange({Protocol::V2, 3, wire::Write{64, {1}}}).front().bytes) ==
        "id=3 error=0x00");
}

TEST_CASE("A hardware_error window opens and closes on the clock, without traffic",
          "[faults][bus]") {
  FaultRig f;
  f.add(
      R"({"action":"hardware_error","kind":"encoder","match":{"servos":[1]},"from_ms":50,"until_ms":60})");
  f.rig.run(40ms);
  CHECK(f.servo(0).motion().injected() == 0);
  f.rig.run(15ms);
  CHECK(f.servo(0).motion().injected() == model::fault_set(model::HardwareFault::Encoder));
  f.rig.run(10ms);
  CHECK(f.servo(0).motion().injected() == 0);
}

TEST_CASE("silence: the servo neither hears nor answers, and a Sync Read chain breaks at it",
          "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"silence","match":{"servos":[2]}})");
  CHECK(f.exchange({Protocol::V2, 2, wire::Ping{}}).empty());
  f.exchange({Protocol::V2, 2, wire::Write{65, {1}}});
  CHECK(f.servo(1).table().get("led") == 0);
  const auto d = f.exchange({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {1, 2, 3}}});
  REQUIRE(d.size() == 1);
  CHECK(status_text(d.front().bytes).rfind("id=1 ", 0) == 0);
}

TEST_CASE("silence_until_reboot: silent after it fires, a Reboot brings the servo back",
          "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"silence_until_reboot","match":{"servos":[1]},"after":1,"count":1})");
  CHECK(f.exchange(kPing1).size() == 1);
  CHECK(f.exchange(kPing1).empty());  // fired
  CHECK(f.exchange(kPing1).empty());  // the rule is spent, the servo stays silent
  f.exchange({Protocol::V2, 1, wire::Write{65, {1}}});
  CHECK(f.servo(0).table().get("led") == 0);
  CHECK(f.exchange({Protocol::V2, 1, wire::Reboot{}}).empty());  // heard, not answered
  f.rig.run(1s);
  CHECK(f.exchange(kPing1).size() == 1);
}

TEST_CASE("A power cycle also ends silence_until_reboot", "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"silence_until_reboot","match":{"servos":[1]}})");
  CHECK(f.exchange(kPing1).empty());
  f.injector.clear();
  f.rig.bus.power_on(f.servo(0));
  f.rig.run(1s);
  CHECK(f.exchange(kPing1).size() == 1);
}

TEST_CASE("eeprom_busy: after an EEPROM write the servo is deaf for the time per byte",
          "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"eeprom_busy","us_per_byte":10000})");
  // A RAM write: no delay.
  f.rig.send({Protocol::V2, 1, wire::Write{65, {1}}});
  f.rig.run(10ms);
  f.rig.link.clear();
  f.rig.send(kPing1);
  f.rig.run(10ms);
  CHECK(f.rig.link.deliveries().size() == 1);
  // Return Delay Time (address 9, EEPROM) and Drive Mode (10): two bytes, 20 ms.
  f.rig.link.clear();
  f.rig.send({Protocol::V2, 1, wire::Write{9, {100, 0}}});
  f.rig.run(6ms);
  REQUIRE(f.rig.link.deliveries().size() == 1);  // the Write itself is answered
  f.rig.link.clear();
  f.rig.send(kPing1);
  f.rig.run(5ms);
  CHECK(f.rig.link.deliveries().empty());  // 6 ms after the write: still busy
  f.rig.run(20ms);
  f.rig.send(kPing1);
  f.rig.run(5ms);
  CHECK(f.rig.link.deliveries().size() == 1);
}

TEST_CASE("Matching on instruction and address range picks the packets", "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"drop_reply","match":{"instruction":"read","address":[132,135]}})");
  CHECK(f.exchange({Protocol::V2, 1, wire::Read{132, 4}}).empty());
  CHECK(f.exchange({Protocol::V2, 1, wire::Read{128, 4}}).size() == 1);
  CHECK(f.exchange({Protocol::V2, 1, wire::Read{126, 10}}).empty());  // overlaps
  CHECK(f.exchange(kPing1).size() == 1);
}

TEST_CASE("Reply faults reach a Fast Sync Read packet", "[faults][bus]") {
  FaultRig f;
  f.add(R"({"action":"corrupt_crc","match":{"servos":[3]}})");
  const auto d = f.exchange({Protocol::V2, kBroadcast, wire::FastSyncRead{{132, 4, {1, 2, 3}}}});
  REQUIRE(d.size() == 1);
  wire::Framer framer(Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(d.front().bytes, sim::SimTime{}, events);
  REQUIRE(events.size() == 1);
  CHECK(std::holds_alternative<wire::FramingError>(events.front()));
}

TEST_CASE("Random faults replay exactly with the same seed", "[faults][bus]") {
  const auto run = [](std::uint64_t seed) {
    faults::Injector injector(seed);
    BusRig rig;
    rig.add("xm430-w350", 1);
    faults::PortFaults port_faults{rig.scheduler, rig.bus.servos()};
    port_faults.set_rules(&injector, "dxl0");
    rig.bus.set_faults(&port_faults);
    injector.add(
        faults::parse_rule(nlohmann::json::parse(R"({"action":"flip_bits","probability":0.3})")),
        {});
    injector.add(
        faults::parse_rule(nlohmann::json::parse(R"({"action":"drop_reply","probability":0.1})")),
        {});
    for (int i = 0; i < 200; ++i) {
      rig.send(kPing1);
      rig.run(10ms);
    }
    return rig.link.deliveries();
  };
  const auto a = run(42);
  CHECK(a == run(42));
  CHECK(a != run(43));
  CHECK(a.size() < 200);
}

TEST_CASE(
    "Protocol 1.0: a corrupted instruction gets the Checksum Error bit, a wrong ID a valid "
    "checksum",
    "[faults][bus]") {
  faults::Injector injector(1);
  BusRig rig;
  rig.add("ax-12a", 1);
  faults::PortFaults port_faults{rig.scheduler, rig.bus.servos()};
  port_faults.set_rules(&injector, "dxl0");
  rig.bus.set_faults(&port_faults);
  constexpr std::uint32_t kAxBaud = 1'000'000;
  const wire::InstructionPacket ping{Protocol::V1, 1, wire::Ping{}};
  const auto id = injector.add(
      faults::parse_rule(nlohmann::json::parse(R"({"action":"corrupt_instruction"})")), {});
  rig.send(ping, kAxBaud);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(status_text(rig.link.deliveries().front().bytes, Protocol::V1) == "id=1 error=0x10");
  injector.remove(id);
  injector.add(faults::parse_rule(nlohmann::json::parse(R"({"action":"wrong_id","id":5})")), {});
  rig.link.clear();
  rig.send(ping, kAxBaud);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(status_text(rig.link.deliveries().front().bytes, Protocol::V1) == "id=5 error=0x00");
}
