// The fault state of one port on its own, without a bus: what each hook answers and what it
// leaves on the servos, on the virtual clock.
#include <catch2/catch.hpp>

#include "faults/port_faults.hpp"
#include "faults/rule_parser.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;

namespace {

/// XM430-W350 servos with `ids`, numbered 0, 1, ... as on a bus.
faults::PortFaults::Servos xm430s(std::initializer_list<std::uint8_t> ids) {
  faults::PortFaults::Servos servos;
  for (const std::uint8_t id : ids) {
    servos.push_back(std::make_unique<model::Servo>(test::shipped_model("xm430-w350"), id));
  }
  return servos;
}

/// Two XM430-W350 (IDs 1 and 2) on port "dxl0" under an injector of seed 1.
struct Port {
  sim::Scheduler scheduler;
  faults::Injector injector{1};
  faults::PortFaults::Servos servos = xm430s({1, 2});
  model::Servo& one = *servos[0];
  model::Servo& two = *servos[1];
  faults::PortFaults faults{scheduler, servos};

  Port() { faults.set_rules(&injector, "dxl0"); }
  void add(const std::string& rule) {
    injector.add(faults::parse_rule(nlohmann::json::parse(rule)), scheduler.now());
  }
};

bus::HeardPacket packet_to(std::uint8_t id, wire::InstructionCode code,
                           const wire::InstructionPacket* decoded, sim::SimTime end) {
  return {wire::Protocol::V2, id, wire::to_byte(code), decoded, end};
}

}  // namespace

TEST_CASE("Without rules every hook answers that nothing happens", "[faults]") {
  sim::Scheduler scheduler;
  const faults::PortFaults::Servos servos = xm430s({1});
  faults::PortFaults faults{scheduler, servos};
  CHECK_FALSE(faults.active());
  const auto heard = packet_to(1, wire::InstructionCode::Ping, nullptr, {});
  const bus::Hearing hearing = faults.hear(heard, 0);
  CHECK(hearing.hears);
  CHECK(hearing.answers);
  CHECK(hearing.extra_delay == 0ns);
  CHECK_FALSE(faults.instruction(heard, {1}).any());
  CHECK(faults.injected() == 0);
}

TEST_CASE("A servo silent until reboot hears only a Reboot to its ID, and does not answer it",
          "[faults]") {
  Port port;
  port.add(R"({"action":"silence_until_reboot","match":{"servos":[1]},"count":1})");
  const wire::InstructionPacket ping{wire::Protocol::V2, 1, wire::Ping{}};
  const wire::InstructionPacket reboot{wire::Protocol::V2, 1, wire::Reboot{}};
  CHECK_FALSE(port.faults.hear(packet_to(1, wire::InstructionCode::Ping, &ping, {}), 0).hears);
  // The rule is spent; the silence stays.
  CHECK_FALSE(port.faults.hear(packet_to(1, wire::InstructionCode::Ping, &ping, {}), 0).hears);
  // A damaged Reboot is not one.
  CHECK_FALSE(port.faults.hear(packet_to(1, wire::InstructionCode::Reboot, nullptr, {}), 0).hears);
  const bus::Hearing on_reboot =
      port.faults.hear(packet_to(1, wire::InstructionCode::Reboot, &reboot, {}), 0);
  CHECK(on_reboot.hears);
  CHECK_FALSE(on_reboot.answers);
  port.faults.rebooted(0);
  CHECK(port.faults.hear(packet_to(1, wire::InstructionCode::Ping, &ping, {}), 0).hears);
  CHECK(port.faults.injected() == 1);
}

TEST_CASE("The hooks are active while a rule is set or a servo keeps the state a rule left",
          "[faults]") {
  Port port;
  CHECK_FALSE(port.faults.active());  // an injector without rules changes nothing
  port.add(R"({"action":"silence_until_reboot","match":{"servos":[1]}})");
  CHECK(port.faults.active());
  const wire::InstructionPacket ping{wire::Protocol::V2, 1, wire::Ping{}};
  CHECK_FALSE(port.faults.hear(packet_to(1, wire::InstructionCode::Ping, &ping, {}), 0).hears);
  port.injector.clear();
  CHECK(port.faults.active());  // the silence outlives the rule
  port.faults.rebooted(0);
  CHECK_FALSE(port.faults.active());
}

TEST_CASE("eeprom_busy keeps a servo deaf for the EEPROM bytes it stored, until powered on",
          "[faults]") {
  Port port;
  port.add(R"({"action":"eeprom_busy","us_per_byte":1000})");
  const sim::SimTime end = port.scheduler.now() + 1ms;
  const std::vector<std::uint8_t> id_and_baud = {7, 3};  // ID (7) and Baud Rate (8): EEPROM
  const wire::InstructionPacket write{wire::Protocol::V2, 1, wire::Write{7, id_and_baud}};
  const auto heard = packet_to(1, wire::InstructionCode::Write, &write, end);
  // Nothing was stored: the table does not hold the bytes, so the servo is not busy.
  port.faults.wrote(heard, 0, 7, id_and_baud);
  CHECK(port.faults.available(0, end));
  port.one.table().set("id", 7);
  port.one.table().set("baud_rate", 3);
  port.faults.wrote(heard, 0, 7, id_and_baud);
  CHECK_FALSE(port.faults.available(0, end + 2ms - 1ns));
  CHECK(port.faults.available(0, end + 2ms));
  CHECK(port.faults.available(1, end));
  port.faults.powered_on(0);
  CHECK(port.faults.available(0, end));
}

TEST_CASE("hardware_error rules reach the servos when they change and when their window opens",
          "[faults]") {
  Port port;
  port.add(R"({"action":"hardware_error","kind":"overheating","match":{"servos":[2]}})");
  CHECK(port.one.motion().injected() == 0);
  CHECK(port.two.motion().injected() == model::fault_set(model::HardwareFault::Overheating));
  port.injector.clear();
  CHECK(port.two.motion().injected() == 0);
  port.add(R"({"action":"hardware_error","kind":"encoder","from_ms":5,"until_ms":8})");
  CHECK(port.one.motion().injected() == 0);
  port.scheduler.advance_by(5ms);
  CHECK(port.one.motion().injected() == model::fault_set(model::HardwareFault::Encoder));
  port.scheduler.advance_by(3ms);
  CHECK(port.one.motion().injected() == 0);
}
