// The injector's triggers (after, count, probability, time window), matching, hardware-error
// states and the byte damage of wire faults, on hand-made packet facts.
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>

#include "faults/injector.hpp"
#include "faults/packet_mangling.hpp"
#include "faults/rule_parser.hpp"
#include "wire/framer.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using faults::PacketFacts;
using nlohmann::json;

namespace {

faults::Rule rule(const std::string& text) {
  return faults::parse_rule(json::parse(text));
}

/// A Read of Present Position (132, 4 bytes) from servo `id` on dxl0 at `at`.
PacketFacts read_from(std::uint8_t id, sim::SimTime at = {}) {
  return {"dxl0", 0x02, {id}, std::pair<std::uint16_t, std::uint16_t>{132, 135}, at};
}

/// Which of `n` replies to read_from(1) the injector drops, as a string of 0 and 1.
std::string drops(faults::Injector& injector, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) {
    std::vector<std::uint8_t> bytes{1, 2, 3};
    out += injector.reply(read_from(1), bytes, wire::Protocol::V2).dropped ? '1' : '0';
  }
  return out;
}

}  // namespace

TEST_CASE("after lets matching packets pass, count limits the firings", "[faults]") {
  faults::Injector injector(1);
  const auto id = injector.add(rule(R"({"action":"drop_reply","after":2,"count":3})"), {});
  CHECK(drops(injector, 8) == "00111000");
  CHECK(injector.rules().front().id == id);
  CHECK(injector.rules().front().matched == 8);
  CHECK(injector.rules().front().fired == 3);
}

TEST_CASE("probability draws from the rule's own stream: the same seed replays the same faults",
          "[faults]") {
  const auto pattern = [](std::uint64_t seed, bool other_rule_first) {
    faults::Injector injector(seed);
    if (other_rule_first) {
      injector.add(rule(R"({"action":"delay_reply","us":5,"probability":0.5})"), {});
      injector.remove(1);
    }
    injector.add(rule(R"({"action":"drop_reply","probability":0.05})"), {});
    return drops(injector, 10000);
  };
  const std::string a = pattern(7, false);
  CHECK(a == pattern(7, false));
  CHECK(a != pattern(8, false));
  // Rule ids name the streams: a rule with another id draws other values.
  CHECK(a != pattern(7, true));
  const auto fired = std::count(a.begin(), a.end(), '1');
  CHECK(fired > 400);  // 5 % of 10,000 is 500; the binomial spread is about 22
  CHECK(fired < 600);
}

TEST_CASE("A rule matches on port, servos, instruction and overlapping addresses", "[faults]") {
  const faults::Match m =
      rule(
          R"({"action":"drop_reply","match":{"port":"dxl0","servos":[3,4],"instruction":["read","sync_read"],"address":[130,133]}})")
          .match;
  CHECK(faults::matches(m, read_from(3)));
  CHECK(faults::matches(m, read_from(4)));
  CHECK_FALSE(faults::matches(m, read_from(5)));
  PacketFacts other_port = read_from(3);
  other_port.port = "dxl1";
  CHECK_FALSE(faults::matches(m, other_port));
  PacketFacts write = read_from(3);
  write.instruction = 0x03;
  CHECK_FALSE(faults::matches(m, write));
  PacketFacts low = read_from(3);
  low.span = {{126, 129}};
  CHECK_FALSE(faults::matches(m, low));
  low.span = {{126, 130}};
  CHECK(faults::matches(m, low));
  PacketFacts ping = read_from(3);
  ping.span.reset();  // an instruction without addresses never matches an address range
  CHECK_FALSE(faults::matches(m, ping));
  PacketFacts group = read_from(1);
  group.instruction = 0x82;
  group.ids = {1, 2, 4};  // a Sync Read listing servo 4
  CHECK(faults::matches(m, group));
}

TEST_CASE("An instruction name matches by what the byte means in the port's protocol", "[faults]") {
  const faults::Match reset =
      rule(R"({"action":"drop_reply","match":{"instruction":"factory_reset"}})").match;
  const faults::Match status_reset =
      rule(R"({"action":"drop_reply","match":{"instruction":"status_reset"}})").match;
  PacketFacts dynamixel = read_from(1);
  dynamixel.instruction = 0x06;  // DYNAMIXEL's Factory Reset
  PacketFacts feetech = dynamixel;
  feetech.protocol = wire::Protocol::Feetech;  // FEETECH's Parameter Recovery
  CHECK(faults::matches(reset, dynamixel));
  CHECK_FALSE(faults::matches(reset, feetech));
  feetech.instruction = 0x0A;  // FEETECH's Status Reset; no DYNAMIXEL instruction
  dynamixel.instruction = 0x0A;
  CHECK(faults::matches(status_reset, feetech));
  CHECK_FALSE(faults::matches(status_reset, dynamixel));
  CHECK_THROWS_WITH(rule(R"({"action":"drop_reply","match":{"instruction":"restart_all"}})"),
                    Catch::Contains("parameter_recovery") && Catch::Contains("fast_bulk_read"));
}

TEST_CASE("A time window counts from when the rule was added", "[faults]") {
  faults::Injector injector(1);
  const sim::SimTime added = sim::SimTime{} + 100ms;
  injector.add(rule(R"({"action":"drop_reply","from_ms":10,"until_ms":20})"), added);
  const auto dropped_at = [&](sim::SimDuration t) {
    std::vector<std::uint8_t> bytes{1};
    return injector.reply(read_from(1, added + t), bytes, wire::Protocol::V2).dropped;
  };
  CHECK_FALSE(dropped_at(9ms));
  CHECK(dropped_at(10ms));
  CHECK(dropped_at(19ms));
  CHECK_FALSE(dropped_at(20ms));
  CHECK(injector.rules().front().matched == 2);  // outside the window nothing counts
}

TEST_CASE("hardware_error rules give each servo its set of errors, windows included", "[faults]") {
  faults::Injector injector(1);
  const sim::SimTime t0{};
  injector.add(rule(R"({"action":"hardware_error","kind":"overheating","match":{"servos":[3]}})"),
               t0);
  const auto late = injector.add(
      rule(
          R"({"action":"hardware_error","kind":"encoder","match":{"port":"dxl0"},"from_ms":5,"until_ms":8})"),
      t0);
  const model::FaultSet heat = model::fault_set(model::HardwareFault::Overheating);
  const model::FaultSet encoder = model::fault_set(model::HardwareFault::Encoder);
  CHECK(injector.hardware_faults("dxl0", 3, t0) == heat);
  CHECK(injector.hardware_faults("dxl0", 2, t0) == 0);
  CHECK(injector.hardware_faults("dxl0", 3, t0 + 6ms) == (heat | encoder));
  CHECK(injector.hardware_faults("dxl1", 2, t0 + 6ms) == 0);
  CHECK(injector.next_state_change(t0) == t0 + 5ms);
  CHECK(injector.next_state_change(t0 + 5ms) == t0 + 8ms);
  CHECK(injector.next_state_change(t0 + 8ms) == std::nullopt);
  int changes = 0;
  const auto subscription = injector.subscribe([&] { ++changes; });
  CHECK(injector.remove(late));
  CHECK_FALSE(injector.remove(late));
  CHECK(changes == 1);
  CHECK(injector.clear() == 1);
  CHECK(changes == 2);
  injector.unsubscribe(subscription);
  injector.add(faults::parse_rule(nlohmann::json::parse(R"({"action":"drop_reply"})")), t0);
  CHECK(changes == 2);
  CHECK(injector.hardware_faults("dxl0", 3, t0) == 0);
}

TEST_CASE("Wire damage: a broken check, flipped bits, a new ID with a valid check", "[faults]") {
  const std::vector<std::uint8_t> v2 =
      wire::encode_status({wire::Protocol::V2, 1, 0, {0x06, 0x04, 0x26}});
  const std::vector<std::uint8_t> v1 = wire::encode_status({wire::Protocol::V1, 1, 0, {0x20}});
  const std::vector<std::uint8_t> feetech =
      wire::encode_status({wire::Protocol::Feetech, 1, 0, {0x00, 0x08}});
  const auto heard = [](const std::vector<std::uint8_t>& bytes, wire::Protocol protocol) {
    wire::Framer framer(protocol);
    std::vector<wire::FramerEvent> events;
    framer.feed(bytes, sim::SimTime{}, events);
    REQUIRE(events.size() == 1);
    return events.front();
  };

  for (const auto& [packet, protocol] :
       {std::pair{v2, wire::Protocol::V2}, std::pair{v1, wire::Protocol::V1},
        std::pair{feetech, wire::Protocol::Feetech}}) {
    auto broken = packet;
    faults::break_check(broken);
    const auto event = heard(broken, protocol);
    REQUIRE(std::holds_alternative<wire::FramingError>(event));
    CHECK(std::get<wire::FramingError>(event).kind == wire::FramingErrorKind::BadCheck);

    auto moved = packet;
    faults::set_id(moved, protocol, 7);
    const auto frame = heard(moved, protocol);
    REQUIRE(std::holds_alternative<wire::Frame>(frame));
    CHECK(std::get<wire::Frame>(frame).id == 7);
  }

  sim::RandomStream stream(3);
  auto flipped = v2;
  faults::flip_bits(flipped, 5, stream);
  int differing = 0;
  for (std::size_t i = 0; i < v2.size(); ++i) {
    differing += std::popcount(static_cast<unsigned>(v2[i] ^ flipped[i]));
  }
  CHECK(differing == 5);
  std::vector<std::uint8_t> tiny{0x0F};
  faults::flip_bits(tiny, 64, stream);  // more bits than there are: every bit flips
  CHECK(tiny == std::vector<std::uint8_t>{0xF0});
}
