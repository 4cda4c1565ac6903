// The bus answers as a chain of real servos would: byte-exact status packets at exact times on
// the virtual clock (docs/bus.md).
#include <catch2/catch.hpp>

#include "bus_rig.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using test::BusRig;
using test::kBroadcast;
using test::kXProcessing;
using test::kXReturnDelay;
using test::line;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

TEST_CASE("Line time is 10 bits per byte at the baud rate, rounded up to the nanosecond",
          "[bus][timing]") {
  CHECK(bus::wire_time(10, 57600) == 1'736'112ns);
  CHECK(bus::wire_time(1, 1'000'000) == 10'000ns);
  CHECK(bus::baud_matches(57600, 57600));
  CHECK(bus::baud_matches(58600, 57600));   // 1.7 %
  CHECK(!bus::baud_matches(60000, 57600));  // 4.2 %
  CHECK(!bus::baud_matches(115200, 57600));
}

TEST_CASE("A Ping is answered with the e-Manual's bytes when its last byte would arrive",
          "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  const std::size_t sent = rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  const auto& reply = rig.link.deliveries()[0];
  // protocol2.md Ping Example 1 with XM430-W350's model number (1020 = 0x03FC) and firmware 45.
  CHECK(test::status_text(reply.bytes) == "id=1 error=0x00 params=FC 03 2D");
  CHECK(reply.at ==
        sim::SimTime{} + line(sent) + kXProcessing + kXReturnDelay + line(reply.bytes.size()));
  CHECK(ns_since_start(reply.at) == 1'736'112 + 50'000 + 500'000 + 2'430'556);
}

TEST_CASE("Broadcast Ping of 5 servos: replies in ascending ID order, each after the previous",
          "[bus][timing]") {
  BusRig rig;
  for (const std::uint8_t id : {4, 2, 5, 1, 3}) {
    rig.add("xm430-w350", id);
  }
  const std::size_t sent = rig.send({Protocol::V2, kBroadcast, wire::Ping{}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 5);
  sim::SimTime end = sim::SimTime{} + line(sent);
  for (std::size_t i = 0; i < d.size(); ++i) {
    CHECK(test::status_text(d[i].bytes).rfind("id=" + std::to_string(i + 1) + " ", 0) == 0);
    end += kXProcessing + kXReturnDelay + line(d[i].bytes.size());
    CHECK(d[i].at == end);
  }
}

TEST_CASE("Read and Write of 1, 2 and 4 bytes and across items", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{116, {0x00, 0x02, 0x00, 0x00}}});  // Goal Position 512
  rig.run();
  rig.send({Protocol::V2, 1, wire::Write{65, {0x01}}});  // LED
  rig.run();
  rig.send({Protocol::V2, 1, wire::Read{116, 4}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::Read{0, 2}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::Read{64, 2}});  // Torque Enable and LED
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 5);
  CHECK(test::status_text(d[0].bytes) == "id=1 error=0x00");
  CHECK(test::status_text(d[1].bytes) == "id=1 error=0x00");
  CHECK(test::status_text(d[2].bytes) == "id=1 error=0x00 params=00 02 00 00");
  CHECK(test::status_text(d[3].bytes) == "id=1 error=0x00 params=FC 03");
  CHECK(test::status_text(d[4].bytes) == "id=1 error=0x00 params=00 01");
}

TEST_CASE("Errors come back as 2.0 error numbers and 1.0 error bits", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("ax-12a", 2).table().set("baud_rate", 34);  // 57,143 bps: within 3 % of 57,600
  rig.bus.servos()[1]->commit_deferred();
  rig.send({Protocol::V2, 1, wire::Write{0, {0x00, 0x00}}});  // read-only
  rig.run();
  rig.send({Protocol::V2, 1, wire::Read{700, 1}});  // beyond the table
  rig.run();
  rig.send({Protocol::V2, 1, wire::UnknownInstruction{0x7E, {}}});
  rig.run();
  rig.send({Protocol::V1, 2, wire::Write{30, {0x00, 0x04}}});  // Goal Position 1024 > 1023
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 4);
  CHECK(test::status_text(d[0].bytes) == "id=1 error=0x07");
  CHECK(test::status_text(d[1].bytes) == "id=1 error=0x07");
  CHECK(test::status_text(d[2].bytes) == "id=1 error=0x02");
  CHECK(test::status_text(d[3].bytes, Protocol::V1) == "id=2 error=0x08");
}

TEST_CASE("Sync Read of 3 servos replies in list order with exact start times", "[bus][timing]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2, 3}) {
    rig.add("xm430-w350", id).table().set("present_position", std::int64_t{100} * id);
  }
  rig.bus.servos()[2]->table().set("return_delay_time", 10);  // ID 3 answers after 20 us
  rig.bus.servos()[2]->commit_deferred();
  const std::size_t sent = rig.send({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {3, 1, 2}}});
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 3);
  CHECK(test::status_text(d[0].bytes) == "id=3 error=0x00 params=2C 01 00 00");
  CHECK(test::status_text(d[1].bytes) == "id=1 error=0x00 params=64 00 00 00");
  CHECK(test::status_text(d[2].bytes) == "id=2 error=0x00 params=C8 00 00 00");
  const sim::SimTime first = sim::SimTime{} + line(sent) + kXProcessing + 20us + line(15);
  CHECK(d[0].at == first);
  CHECK(d[1].at == first + kXProcessing + kXReturnDelay + line(15));
  CHECK(d[2].at == d[1].at + kXProcessing + kXReturnDelay + line(15));
}

TEST_CASE("A listed ID that does not answer breaks the Sync Read chain after it", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 3);
  rig.send({Protocol::V2, kBroadcast, wire::SyncRead{132, 4, {1, 2, 3}}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes).rfind("id=1 ", 0) == 0);
}

TEST_CASE("Fast Sync Read is one unstuffed packet from 0xFE with the delay charged once",
          "[bus][timing]") {
  BusRig rig;
  for (const std::uint8_t id : {3, 7, 4}) {
    rig.add("xc330-t288", id);
  }
  rig.bus.servos()[0]->table().set("present_position", 166);
  rig.bus.servos()[1]->table().set("present_position", 2079);
  rig.bus.servos()[2]->table().set("present_position", 1023);
  const std::size_t sent =
      rig.send({Protocol::V2, kBroadcast, wire::FastSyncRead{{132, 4, {3, 7, 4}}}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  const auto& reply = rig.link.deliveries()[0];
  // protocol2.md Fast Sync Read example: the same three positions, the same bytes.
  CHECK(reply.bytes == Bytes{0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x19, 0x00, 0x55, 0x00, 0x03, 0xA6,
                             0x00, 0x00, 0x00, 0x84, 0x08, 0x00, 0x07, 0x1F, 0x08, 0x00, 0x00,
                             0x16, 0xCA, 0x00, 0x04, 0xFF, 0x03, 0x00, 0x00, 0xD1, 0x9E});
  CHECK(reply.at ==
        sim::SimTime{} + line(sent) + kXProcessing + kXReturnDelay + line(reply.bytes.size()));
}

TEST_CASE("Protocol 1.0 Bulk Read replies are chained in list order", "[bus][timing]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2}) {
    auto& servo = rig.add("mx-28", id);  // factory: 57,143 bps, Return Delay Time 250
    servo.table().set("goal_position", 0x8000 - 0x10000);
  }
  const std::size_t sent =
      rig.send({Protocol::V1, kBroadcast, wire::BulkRead{{{1, 30, 2}, {2, 36, 2}}}}, 57142);
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 2);
  CHECK(test::status_text(d[0].bytes, Protocol::V1) == "id=1 error=0x00 params=00 80");
  CHECK(test::status_text(d[1].bytes, Protocol::V1).rfind("id=2 error=0x00 params=", 0) == 0);
  const auto bps = rig.bus.servos()[0]->baud_bps();
  const sim::SimTime first =
      sim::SimTime{} + line(sent, 57142) + kXProcessing + kXReturnDelay + line(8, bps);
  CHECK(d[0].at == first);
  CHECK(d[1].at == first + kXProcessing + kXReturnDelay + line(8, bps));
}

TEST_CASE("Reg Write to 3 servos, then one broadcast Action moves them together", "[bus]") {
  BusRig rig;
  for (const std::uint8_t id : {1, 2, 3}) {
    rig.add("xm430-w350", id);
    rig.send({Protocol::V2, id, wire::RegWrite{116, {0x00, 0x01, 0x00, 0x00}}});
    rig.run();
  }
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("goal_position") == 2048);
    CHECK(s->table().get("registered_instruction") == 1);
  }
  rig.link.clear();
  rig.send({Protocol::V2, kBroadcast, wire::Action{}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  for (const auto& s : rig.bus.servos()) {
    CHECK(s->table().get("goal_position") == 256);
    CHECK(s->table().get("registered_instruction") == 0);
  }
}

TEST_CASE("A new ID and baud rate take effect after the status that confirms them", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{7, {9}}});
  // Before the status is out, ID 1 still answers.
  CHECK(rig.bus.servos()[0]->id() == 1);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=1 error=0x00");
  CHECK(rig.bus.servos()[0]->id() == 9);
  rig.send({Protocol::V2, 9, wire::Write{8, {3}}});  // 1 Mbps
  rig.run();
  rig.link.clear();
  rig.send({Protocol::V2, 9, wire::Ping{}});  // still at 57,600: noise to the servo
  rig.run();
  CHECK(rig.link.deliveries().empty());
  rig.send({Protocol::V2, 9, wire::Ping{}}, 1'000'000);
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("A rebooting servo answers the Reboot, then stays silent for its boot time", "[bus]") {
  BusRig rig;
  auto& servo = rig.add("xm430-w350", 1);
  servo.table().set("led", 1);
  rig.send({Protocol::V2, 1, wire::Reboot{}});
  rig.run(10ms);
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(servo.table().get("led") == 0);
  CHECK(rig.bus.booting(servo));
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run(10ms);
  CHECK(rig.link.deliveries().size() == 1);
  rig.run(500ms);  // boot_ms = 400
  CHECK(!rig.bus.booting(servo));
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run(10ms);
  CHECK(rig.link.deliveries().size() == 2);
}

TEST_CASE("Protocol 1.0 and 2.0 servos share a bus and each hears only its protocol", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  auto& x_in_v1 = rig.add("xm430-w350", 2);
  x_in_v1.table().set("protocol_type", 1);  // an X servo switched to Protocol 1.0
  x_in_v1.commit_deferred();
  rig.send({Protocol::V2, kBroadcast, wire::Ping{}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes).rfind("id=1 ", 0) == 0);
  rig.link.clear();
  rig.send({Protocol::V1, 2, wire::Read{7, 1}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes, Protocol::V1) ==
        "id=2 error=0x00 params=02");
}

TEST_CASE("Two servos with the same ID both answer and the client gets a garbled packet", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1).table().set("present_temperature", 0x21);
  rig.add("xm430-w350", 1).table().set("present_temperature", 0x12);
  rig.send({Protocol::V2, 1, wire::Read{146, 1}});
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  wire::Framer framer(Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(rig.link.deliveries()[0].bytes, sim::SimTime{}, events);
  CHECK(wire::FramingErrorKind::BadCheck == std::get<wire::FramingError>(events.at(0)).kind);
  CHECK(rig.bus.stats().id_conflicts == 1);
}

TEST_CASE("A packet with a bad CRC is answered with CRC Error by the servo of that ID", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  auto bytes = wire::encode_instruction({Protocol::V2, 1, wire::Read{132, 4}});
  bytes.back() ^= 0x01;
  rig.bus.receive(bytes, rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=1 error=0x03");
  CHECK(rig.bus.stats().bad_checks == 1);
}

TEST_CASE("An instruction sent while replies are due drops them and counts a collision", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.send({Protocol::V2, 1, wire::Write{65, {1}}});
  rig.send({Protocol::V2, 1, wire::Ping{}});  // the client did not wait
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  CHECK(test::status_text(rig.link.deliveries()[0].bytes) == "id=1 error=0x00 params=FC 03 2D");
  CHECK(rig.bus.stats().collisions == 1);
  CHECK(rig.bus.servos()[0]->table().get("led") == 1);  // the first write still happened
}

TEST_CASE("In one write, the second instruction follows the first on the line and drops its reply",
          "[bus][timing]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  auto bytes = wire::encode_instruction({Protocol::V2, 1, wire::Write{65, {1}}});
  const std::size_t write_size = bytes.size();
  const auto ping = wire::encode_instruction({Protocol::V2, 1, wire::Ping{}});
  bytes.insert(bytes.end(), ping.begin(), ping.end());
  rig.bus.receive(bytes, rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  const auto& d = rig.link.deliveries();
  REQUIRE(d.size() == 1);
  CHECK(test::status_text(d[0].bytes) == "id=1 error=0x00 params=FC 03 2D");
  CHECK(d[0].at == sim::SimTime{} + line(write_size) + line(ping.size()) + kXProcessing +
                       kXReturnDelay + line(d[0].bytes.size()));
  CHECK(rig.bus.stats().collisions == 1);
  CHECK(rig.bus.servos()[0]->table().get("led") == 1);
}

TEST_CASE("Packets of both protocols in one write: the later one is answered, in any timing",
          "[bus][timing]") {
  const auto v1_ping = wire::encode_instruction({Protocol::V1, 5, wire::Ping{}});
  const auto v2_ping = wire::encode_instruction({Protocol::V2, 1, wire::Ping{}});
  for (const auto& [v1_first, timing] :
       {std::pair{true, bus::ReplyTiming::Modelled}, std::pair{false, bus::ReplyTiming::Modelled},
        std::pair{true, bus::ReplyTiming::Immediate},
        std::pair{false, bus::ReplyTiming::Immediate}}) {
    CAPTURE(v1_first, timing == bus::ReplyTiming::Immediate);
    BusRig rig;
    rig.bus.set_reply_timing(timing);
    rig.add("xm430-w350", 1);
    rig.add("mx-28", 5);  // Protocol 1.0 at 57600 bps
    auto bytes = v1_first ? v1_ping : v2_ping;
    const auto& second = v1_first ? v2_ping : v1_ping;
    bytes.insert(bytes.end(), second.begin(), second.end());
    rig.bus.receive(bytes, rig.scheduler.now(), BusRig::kBaud);
    rig.run();
    const auto& d = rig.link.deliveries();
    REQUIRE(d.size() == 1);
    CHECK(d[0].bytes.size() == (v1_first ? 14U : 6U));  // 2.0 or 1.0 Ping status
    CHECK(rig.bus.stats().collisions == 1);
  }
}

TEST_CASE("Replies the link drops because the client does not read count as unread drops",
          "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.link.set_accepting(false);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  rig.link.set_accepting(true);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
  CHECK(rig.bus.stats().replies == 1);
  CHECK(rig.bus.stats().unread_drops == 1);
}

TEST_CASE("Status Return Level 0 answers only Ping, and broadcast writes are silent", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1).table().set("status_return_level", 0);
  rig.send({Protocol::V2, 1, wire::Read{146, 1}});
  rig.run();
  rig.send({Protocol::V2, 1, wire::Write{65, {1}}});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, wire::Write{65, {0}}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.servos()[0]->table().get("led") == 0);
  rig.send({Protocol::V2, 1, wire::Ping{}});
  rig.run();
  CHECK(rig.link.deliveries().size() == 1);
}

TEST_CASE("Sync Write and Bulk Write are applied without replies", "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  rig.add("xm430-w350", 2);
  rig.send({Protocol::V2, kBroadcast,
            wire::SyncWrite{116, 4, {{1, {0x96, 0, 0, 0}}, {2, {0xAA, 0, 0, 0}}}}});
  rig.run();
  rig.send({Protocol::V2, kBroadcast, wire::BulkWrite{{{1, 65, {1}}, {2, 68, {1}}}}});
  rig.run();
  CHECK(rig.link.deliveries().empty());
  CHECK(rig.bus.servos()[0]->table().get("goal_position") == 150);
  CHECK(rig.bus.servos()[1]->table().get("goal_position") == 170);
  CHECK(rig.bus.servos()[0]->table().get("led") == 1);
  CHECK(rig.bus.servos()[1]->table().get("status_return_level") == 1);
}

TEST_CASE("Immediate reply timing answers at once, in the same order with the same bytes",
          "[bus][timing]") {
  BusRig modelled;
  BusRig immediate;
  immediate.bus.set_reply_timing(bus::ReplyTiming::Immediate);
  const std::vector<wire::InstructionPacket> packets = {
      {Protocol::V2, kBroadcast, wire::Ping{}},
      {Protocol::V2, kBroadcast, wire::SyncRead{7, 1, {3, 1}}},
      {Protocol::V2, kBroadcast, wire::FastSyncRead{{7, 1, {2, 3}}}},
      {Protocol::V2, 2, wire::Read{7, 1}},
  };
  for (BusRig* rig : {&modelled, &immediate}) {
    for (const std::uint8_t id : {1, 2, 3}) {
      rig->add("xm430-w350", id);
    }
  }
  immediate.scheduler.advance_by(7ms);
  for (const auto& packet : packets) {
    modelled.send(packet);
    modelled.run();
    immediate.send(packet);
    immediate.scheduler.run_due();  // nothing is due later than the instruction's arrival
  }
  const auto& now = immediate.link.deliveries();
  REQUIRE(now.size() == 3 + 2 + 1 + 1);
  REQUIRE(modelled.link.deliveries().size() == now.size());
  for (std::size_t i = 0; i < now.size(); ++i) {
    CHECK(now[i].bytes == modelled.link.deliveries()[i].bytes);
    CHECK(now[i].at == sim::SimTime{} + 7ms);
  }
  CHECK(test::status_text(now[3].bytes) == "id=3 error=0x00 params=03");
}

TEST_CASE("The line observer sees every packet heard and every delivery, but not garbage",
          "[bus]") {
  BusRig rig;
  rig.add("xm430-w350", 1);
  std::vector<std::string> seen;
  rig.bus.set_observer(
      {[&](const wire::FramerEvent& event) {
         if (const auto* frame = std::get_if<wire::Frame>(&event)) {
           seen.push_back("heard id=" + std::to_string(frame->id));
         } else {
           seen.emplace_back("heard failure");
         }
       },
       [&](std::span<const std::uint8_t> bytes, sim::SimTime at, Protocol protocol) {
         CHECK(protocol == Protocol::V2);
         seen.push_back("sent " + test::status_text({bytes.begin(), bytes.end()}) + " at " +
                        std::to_string(ns_since_start(at)));
       }});
  const Bytes noise = {0x12, 0x34};
  rig.bus.receive(noise, rig.scheduler.now(), BusRig::kBaud);
  rig.send({Protocol::V2, 1, wire::Write{65, {1}}});
  rig.send({Protocol::V2, 1, wire::Ping{}});  // collides with the Write's status: not sent
  rig.run();
  auto damaged = wire::encode_instruction({Protocol::V2, 1, wire::Ping{}});
  damaged.back() ^= 0xFF;
  rig.bus.receive(damaged, rig.scheduler.now(), BusRig::kBaud);
  rig.run();
  REQUIRE(seen.size() == 5);
  CHECK(seen[0] == "heard id=1");
  CHECK(seen[1] == "heard id=1");
  CHECK(seen[2] == "sent id=1 error=0x00 params=FC 03 2D at " +
                       std::to_string(ns_since_start(rig.link.deliveries()[0].at)));
  CHECK(seen[3] == "heard failure");
  CHECK(seen[4].rfind("sent id=1 error=0x03", 0) == 0);  // CRC Error
}

TEST_CASE("A packet found when the partial one before it timed out is answered from the expiry",
          "[bus]") {
  BusRig rig;
  rig.add("ax-12a", 1);
  // A 1.0 header that announces 32 bytes swallows the Ping behind it until the inter-byte
  // timeout drops it; the framer then finds the Ping in the bytes it held.
  const Bytes bytes{0xFF, 0xFF, 0x05, 0x20, 0xFF, 0xFF, 0x01, 0x02, 0x01, 0xFB};
  rig.bus.receive(bytes, rig.scheduler.now(), 1'000'000);
  rig.run();
  REQUIRE(rig.link.deliveries().size() == 1);
  const auto& reply = rig.link.deliveries()[0];
  CHECK(reply.bytes == Bytes{0xFF, 0xFF, 0x01, 0x02, 0x00, 0xFC});
  // Modelled from the expiry (100 ms for Protocol 1.0), so not "late" by the whole timeout.
  CHECK(reply.at >= sim::SimTime{} + 100ms);
}
