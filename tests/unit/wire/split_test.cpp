// The framers accept any split of the byte stream: every golden packet cut at every boundary,
// byte by byte, and all packets of a protocol back to back in one chunk.
#include <catch2/catch.hpp>

#include "framer_events.hpp"
#include "golden_file.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using sim::SimTime;
using wire::Framer;

TEST_CASE("Every golden packet split at every byte boundary yields the same frame",
          "[wire][split]") {
  for (const auto& p : test::load_golden_packets()) {
    const std::span<const std::uint8_t> bytes(p.bytes);
    for (std::size_t cut = 1; cut < bytes.size(); ++cut) {
      INFO(p.name << " cut at " << cut);
      Framer framer(p.protocol);
      std::vector<wire::FramerEvent> events;
      const SimTime t0{};
      const SimTime t1 = t0 + 1ms;  // within both protocols' inter-byte timeout
      framer.feed(bytes.first(cut), t0, events);
      CHECK(events.empty());
      CHECK(framer.buffered() == cut);
      framer.feed(bytes.subspan(cut), t1, events);
      REQUIRE(events.size() == 1);
      REQUIRE(test::frames_of(events).size() == 1);
      const auto& frame = std::get<wire::Frame>(events[0]);
      CHECK(frame.raw == p.bytes);
      CHECK(frame.first_byte_at == t0);
      CHECK(frame.last_byte_at == t1);
    }
  }
}

TEST_CASE("Every golden packet fed byte by byte yields the same frame", "[wire][split]") {
  for (const auto& p : test::load_golden_packets()) {
    INFO(p.name);
    Framer framer(p.protocol);
    std::vector<wire::FramerEvent> events;
    SimTime t{};
    for (const std::uint8_t b : p.bytes) {
      framer.feed(std::span(&b, 1), t, events);
      t += 100us;
    }
    REQUIRE(test::frames_of(events).size() == 1);
    CHECK(events.size() == 1);
    CHECK(test::frames_of(events)[0].raw == p.bytes);
  }
}

TEST_CASE("All golden packets of a protocol back to back in one chunk come out in order",
          "[wire][split]") {
  for (const auto protocol : {wire::Protocol::V1, wire::Protocol::V2}) {
    const auto packets = test::load_golden_packets(protocol);
    const std::vector<std::uint8_t> stream = test::concatenated(packets);
    Framer framer(protocol);
    std::vector<wire::FramerEvent> events;
    framer.feed(stream, SimTime{}, events);
    const auto frames = test::frames_of(events);
    INFO(test::summary(events));
    REQUIRE(frames.size() == packets.size());
    CHECK(test::errors_of(events).empty());
    for (std::size_t i = 0; i < packets.size(); ++i) {
      CHECK(frames[i].raw == packets[i].bytes);
    }
  }
}

TEST_CASE("A stream cut into chunks of every size from 1 to 17 bytes frames identically",
          "[wire][split]") {
  for (const auto protocol : {wire::Protocol::V1, wire::Protocol::V2}) {
    const auto packets = test::load_golden_packets(protocol);
    const std::vector<std::uint8_t> stream = test::concatenated(packets);
    for (std::size_t chunk = 1; chunk <= 17; ++chunk) {
      INFO("chunk size " << chunk);
      Framer framer(protocol);
      std::vector<wire::FramerEvent> events;
      for (std::size_t at = 0; at < stream.size(); at += chunk) {
        const std::size_t n = std::min(chunk, stream.size() - at);
        framer.feed(std::span(stream).subspan(at, n), SimTime{}, events);
      }
      CHECK(test::errors_of(events).empty());
      CHECK(test::frames_of(events).size() == packets.size());
    }
  }
}

TEST_CASE("Bytes fed with their own arrival times stamp packets and errors with time and offset",
          "[wire][framer]") {
  const auto ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  std::vector<std::uint8_t> bytes = {0x00};  // one garbage byte first
  bytes.insert(bytes.end(), ping.begin(), ping.end());
  bytes.insert(bytes.end(), ping.begin(), ping.end());
  std::vector<SimTime> times;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    times.push_back(SimTime{} + 10us * static_cast<int>(i));
  }
  Framer framer(wire::Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, times, events);
  REQUIRE(events.size() == 3);
  CHECK(std::get<wire::FramingError>(events[0]).at == SimTime{});
  CHECK(wire::offset_of(events[0]) == 0);
  const auto frames = test::frames_of(events);
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].first_byte_at == SimTime{} + 10us);
  CHECK(frames[0].last_byte_at == SimTime{} + 10us * static_cast<int>(ping.size()));
  CHECK(frames[0].offset == 1);
  CHECK(frames[1].first_byte_at == SimTime{} + 10us * static_cast<int>(1 + ping.size()));
  CHECK(frames[1].offset == 1 + ping.size());
  CHECK(framer.fed() == bytes.size());
  CHECK_THROWS_AS(framer.feed(bytes, std::span(times).first(1), events), std::invalid_argument);
}
