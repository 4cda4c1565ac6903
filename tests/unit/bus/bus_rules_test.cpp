// Bus rules beyond plain request and reply: Secondary ID, Bus Watchdog, Protocol 1.0 broadcast
// Ping, the framers' timeout, Bulk Read and Fast Bulk Read layouts, Factory Reset (docs/bus.md).
#include <catch2/catch.hpp>

#include "bus_rig.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using test::BusRig;
using test::kBroadcast;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

TEST_CASE("A Secondary ID group executes RAM writes silently and the ID keeps priority", "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2, 3}) {
    rig.add("xm430-w350", id).table().set("secondary_id", 5);
  }
  rig.add("xm430-w350", 5);                           // a servo whose own ID is 5
  rig.send({Protocol::V2, 5, wire::Write{65, {1}}});  // LED on
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);  // only the servo with ID 5 answers
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=5 error=0x00");
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("led") == 1);
  }
  // EEPROM cannot be changed through the Secondary ID.
  rig.send({Protocol::V2, 5, wire::Write{9, {10}}});  // Return Delay Time
  rig.run();
  CHECK(rig.bus.servos()[0]->table().get("return_delay_time") == 250);
  CHECK(rig.bus.servos()[3]->table().get("return_delay_time") == 10);
}

TEST_CASE("A Sync or Bulk Write block for a Secondary ID reaches its group unless it has its own",
          "[bus]") {
  // Interbotix arms drive a shadow servo (Secondary ID = its master's ID) with group Sync
  // Writes that list the masters only.
  BusRig rig;
  rig.add("xm430-w350", 2);
  rig.add("xm430-w350", 3).table().set("secondary_id", 2);  // the shadow of 2
  rig.add("xm430-w350", 4).table().set("secondary_id", 2);  // listed itself below
  auto led = [&](std::size_t i) { return rig.bus.servos()[i]->table().get("led"); };
  SECTION("Sync Write") {
    rig.send({Protocol::V2, kBroadcast, wire::SyncWrite{65, 1, {{2, {1}}, {4, {0}}}}});
    rig.run();
    CHECK(rig.link.deliveries().empty());
    CHECK(led(0) == 1);
    CHECK(led(1) == 1);  // through its Secondary ID
    CHECK(led(2) == 0);  // its own block has priority
  }
  SECTION("Bulk Write") {
    rig.send({Protocol::V2, kBroadcast, wire::BulkWrite{{{2, 65, {1}}}}});
    rig.run();
    CHECK(led(1) == 1);
  }
  SECTION("EEPROM is not changed through the Secondary ID") {
    rig.send({Protocol::V2, kBroadcast, wire::SyncWrite{9, 1, {{2, {10}}}}});  // Return Delay
    rig.run();
    CHECK(rig.bus.servos()[0]->table().get("return_delay_time") == 10);
    CHECK(rig.bus.servos()[1]->table().get("return_delay_time") == 250);
  }
}

TEST_CASE("Secondary ID 253 and above is off", "[bus]") {
  // Protocol 1.0, where 253 is a unicast Packet ID, so that only the Secondary ID's cut-off keeps
  // the packet from the servo; 252, the highest Secondary ID, shows the same packet would work.
  for (const std::uint8_t secondary : {252, 253}) {
    INFO("Secondary ID " << int{secondary});
    BusRig rig;
    auto& servo = rig.add("xm430-w350", 1);
    auto& table = servo.table();
    table.set("protocol_type", 1);
    servo.commit_deferred();
    table.set("secondary_id", secondary);
    rig.send({Protocol::V1, secondary, wire::Write{65, {1}}});  // LED on
    rig.run();
    CHECK(table.get("led") == (secondary == 252 ? 1 : 0));
  }
}

TEST_CASE("The Bus Watchdog stops a quiet servo and refuses goal writes until it is cleared",
          "[bus][timing]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  servo.table().set("operating_mode", 1);             // velocity control
  rig.send({Protocol::V2, 1, wire::Write{64, {1}}});  // torque on
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{104, {50, 0, 0, 0}}});  // Goal Velocity 50
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{98, {5}}});  // Bus Watchdog 100 ms
  const sim::SimTime armed = rig.scheduler.now();
  rig.run(90ms);
  rig.send({Protocol::V2, 2, wire::Ping{}});  // any packet on the bus is traffic
  const sim::SimTime traffic = rig.scheduler.now();
  rig.run(99ms);
  CHECK(servo.table().get("bus_watchdog") == 5);
  rig.run(10ms);
  CHECK(servo.table().get("bus_watchdog") == -1);
  CHECK(servo.table().get("goal_velocity") == 0);
  CHECK(rig.scheduler.now() - traffic > 100ms);
  CHECK(rig.scheduler.now() - armed > 190ms);
  rig.link.clear();
  rig.send({Protocol::V2, 1, wire::Write{104, {150, 0, 0, 0}}});
  rig.run(10ms);
  CHECK(test::status_text(rig.link.deliveries().at(0).bytes) == "id=1 error=0x04");
  rig.send({Protocol::V2, 1, wire::Write{98, {0}}});  // clears the error
  rig.run(10ms);
  rig.send({Protocol::V2, 1, wire::Write{104, {150, 0, 0, 0}}});
  rig.run(10ms);
  CHECK(test::status_text(rig.link.deliveries().at(2).bytes) == "id=1 error=0x00");
  CHECK(servo.table().get("goal_velocity") == 150);
}

TEST_CASE("The Bus Watchdog is idle while torque is off", "[bus][timing]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{98, {1}}});  // 20 ms, torque off
  rig.run(1s);
  CHECK(servo.table().get("bus_watchdog") == 1);
}

TEST_CASE("Protocol 1.0 servos answer a broadcast Ping at once and their replies collide",
          "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2}) {
    auto& s = rig.add("mx-28", id);
    s.table().set("baud_rate", 16);  // 117,647 bps
    s.commit_deferred();
  }
  rig.send({Protocol::V1, kBroadcast, wire::Ping{}}, 117647);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.bus.stats().id_conflicts == 1);
  // ID 1 and ID 2 ANDed: FF FF 00 02 00 (FC & FB = F8).
  CHECK(rig.link.deliveries()[0].bytes == Bytes{0xFF, 0xFF, 0x00, 0x02, 0x00, 0xF8});
}

TEST_CASE("A partial packet is dropped and counted when the line stays quiet", "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  const auto bytes = wire::encode_instruction({Protocol::V2, 1, wire::Ping{}});
  rig.bus.receive(std::span(bytes).first(6), rig.scheduler.now(), BusRig::kBaud);
  // The timeout runs from the arrival of the last byte, 5 byte times after the first.
  rig.run(test::line(5) + 1500us);
  CHECK(rig.bus.stats().truncated == 0);
  rig.run(1ns);
  CHECK(rig.bus.stats().truncated == 1);
  rig.bus.receive(bytes, rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("Protocol 2.0 Bulk Read reproduces the e-Manual example", "[bus]") {
  BusRig rig;
  rig.add("xm430-w210", 1).table().set("present_input_voltage", 119);
  rig.add("xm430-w210", 2).table().set("present_temperature", 36);
  rig.send({Protocol::V2, kBroadcast, wire::BulkRead{{{1, 144, 2}, {2, 146, 1}}}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(d[0].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x06, 0x00, 0x55, 0x00, 0x77, 0x00, 0xC3, 0x69});
  CHECK(d[1].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0x02, 0x05, 0x00, 0x55, 0x00, 0x24, 0x8B, 0xA9});
}

TEST_CASE("Fast Bulk Read reproduces the e-Manual example", "[bus]") {
  BusRig rig;
  rig.add("xc330-t288", 3).table().set("present_position", 166);
  rig.add("xc330-t288", 7).table().set("present_pwm", 421);
  rig.add("xc330-t288", 4).table().set("present_temperature", 31);
  rig.send(
      {Protocol::V2, kBroadcast, wire::FastBulkRead{{{{3, 132, 4}, {7, 124, 2}, {4, 146, 1}}}}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(rig.link.deliveries()[0].bytes ==
        Bytes{0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x14, 0x00, 0x55, 0x00, 0x03, 0xA6, 0x00, 0x00, 0x00,
              0x67, 0xA4, 0x00, 0x07, 0xA5, 0x01, 0x24, 0x74, 0x00, 0x04, 0x1F, 0xD9, 0xC1});
}

TEST_CASE("A Fast Sync Read whose chain breaks sends a packet cut short", "[bus]") {
  BusRig rig;
  rig.add("xc330-t288", 3);
  rig.add("xc330-t288", 4);
  rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{132, 4, {3, 7, 4}}}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  const Bytes& bytes = rig.link.deliveries()[0].bytes;
  CHECK(bytes.size() == 8 + 8);               // header, 0x55 and ID 3's block only
  CHECK((bytes[5] | (bytes[6] << 8)) == 25);  // LENGTH still announces three blocks
}

TEST_CASE("Fast reads are not answered by models without them", "[bus]") {
  BusRig rig;
  rig.add("2xl430-w250", 1);
  rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{132, 4, {1}}}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
}

TEST_CASE("Factory Reset answers with the old ID, then the servo is back at factory settings",
          "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 7);
  servo.table().set("return_delay_time", 0);
  servo.commit_deferred();
  rig.send({Protocol::V2, 7, wire::FactoryReset{wire::factory_reset::kResetAll}});
  rig.run(10ms);
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=7 error=0x00");
  CHECK(servo.id() == 1);
  CHECK(servo.return_delay() == 500us);
  CHECK(rig.bus.booting(servo));
}

TEST_CASE("Protocol 1.0 Sync Write is applied to every listed servo", "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {0, 1}) {
    auto& s = rig.add("mx-64", id);
    s.table().set("baud_rate", 1);  // 1 Mbps
    s.commit_deferred();
  }
  // protocol1.md Sync Write example: Goal Position and Moving Speed of ID 0 and ID 1.
  rig.send({Protocol::V1, kBroadcast,
            wire::SyncWrite{30, 4, {{0, {0x10, 0x00, 0x50, 0x01}}, {1, {0x20, 0x02, 0x60, 0x03}}}}},
           1'000'000);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.servos()[0]->table().get("goal_position") == 0x010);
  CHECK(rig.bus.servos()[0]->table().get("moving_speed") == 0x150);
  CHECK(rig.bus.servos()[1]->table().get("goal_position") == 0x220);
  CHECK(rig.bus.servos()[1]->table().get("moving_speed") == 0x360);
}

TEST_CASE("A malformed Sync Read sent to a single ID is ignored like a well-formed one", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  // address 132, length 4, and no ID list: broken layout, sent to ID 1.
  const auto bytes = wire::encode_packet(Protocol::V2, 1, 0x82, Bytes{0x84, 0x00, 0x04, 0x00});
  rig.bus.receive(bytes, rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.stats().decode_errors == 1);
}
