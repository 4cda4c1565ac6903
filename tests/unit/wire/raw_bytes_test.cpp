// Every framer event carries the bytes it covers, so that no one outside wire/ has to find them
// again: a frame its packet, a framing error the garbage run, header or partial packet it rejects.
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "framer_events.hpp"
#include "sim/rng.hpp"
#include "wire/framer.hpp"
#include "wire/instruction.hpp"
#include "wire/instruction_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;
using sim::SimTime;
using wire::Framer;
using wire::Protocol;

namespace {

using test::concat;
using test::ping_packet;

using Bytes = std::vector<std::uint8_t>;

Bytes read(Protocol protocol, std::uint8_t id) {
  constexpr std::uint16_t kPresentPosition = 132;
  constexpr std::uint16_t kFourBytes = 4;
  return wire::encode_instruction({protocol, id, wire::Read{kPresentPosition, kFourBytes}});
}

// The events of `stream` fed in one chunk, then expired.
std::vector<wire::FramerEvent> events_of(Protocol protocol, const Bytes& stream) {
  Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  framer.expire(SimTime{} + 1s, events);
  return events;
}

// The bytes of `stream` an event says it covers: from its offset, as many as it counts.
Bytes covered(const Bytes& stream, const wire::FramerEvent& event) {
  const auto* frame = std::get_if<wire::Frame>(&event);
  const std::size_t size =
      frame != nullptr ? frame->raw.size() : std::get<wire::FramingError>(event).bytes;
  const auto first = stream.begin() + static_cast<std::ptrdiff_t>(wire::offset_of(event));
  return {first, first + static_cast<std::ptrdiff_t>(size)};
}

const Bytes& raw_of(const wire::FramerEvent& event) {
  const auto* frame = std::get_if<wire::Frame>(&event);
  return frame != nullptr ? frame->raw : std::get<wire::FramingError>(event).raw;
}

}  // namespace

TEST_CASE("A garbage run carries the bytes skipped", "[wire][framer]") {
  const Bytes junk = {0x13, 0x37, 0x00, 0xFF, 0xFE};
  const auto events = events_of(Protocol::V2, concat({junk, ping_packet(Protocol::V2, 1), junk}));
  REQUIRE(test::summary(events) == "garbage(5) frame(id=1) garbage(5)");
  CHECK(std::get<wire::FramingError>(events[0]).raw == junk);
  CHECK(std::get<wire::FramingError>(events[2]).raw == junk);
}

TEST_CASE("A bad CRC or checksum carries the whole packet as it arrived", "[wire][framer]") {
  for (const auto protocol : {Protocol::V1, Protocol::V2}) {
    Bytes bad = read(protocol, 2);
    bad.back() ^= 0xFF;
    const auto events = events_of(protocol, concat({bad, ping_packet(protocol, 3)}));
    REQUIRE(test::summary(events) == "bad_check(id=2) frame(id=3)");
    CHECK(std::get<wire::FramingError>(events[0]).raw == bad);
  }
}

TEST_CASE("An impossible length carries the header, ID and LENGTH it rejects", "[wire][framer]") {
  // LENGTH 1 is below the 2.0 minimum of 3 (instruction and CRC).
  const Bytes header = {0xFF, 0xFF, 0xFD, 0x00, 0x04, 0x01, 0x00};
  const auto events = events_of(Protocol::V2, concat({header, ping_packet(Protocol::V2, 5)}));
  REQUIRE(test::summary(events) == "impossible_length(id=4) frame(id=5)");
  CHECK(std::get<wire::FramingError>(events[0]).raw == header);
}

TEST_CASE("A packet cut short by the inter-byte timeout carries the bytes that arrived",
          "[wire][framer]") {
  const Bytes whole = read(Protocol::V1, 6);
  const Bytes partial(whole.begin(), whole.end() - 3);
  const auto events = events_of(Protocol::V1, partial);
  REQUIRE(test::summary(events) == "truncated(5)");
  CHECK(std::get<wire::FramingError>(events[0]).raw == partial);
}

TEST_CASE("Every event's bytes are the stream's from its offset on, however the stream is split",
          "[wire][framer]") {
  // Good packets, bad checks, impossible lengths, garbage and pauses past the inter-byte timeout,
  // in a seeded random order and cut into random chunks.
  sim::RandomStream rng(0x5eed);
  for (const auto protocol : {Protocol::V1, Protocol::V2}) {
    std::set<std::string> seen;  // event kinds, to show that the mix covers them all
    const auto timeout = wire::FrameFormat::for_protocol(protocol).inter_byte_timeout;
    for (int round = 0; round < 50; ++round) {
      Framer framer(protocol);
      std::vector<wire::FramerEvent> events;
      Bytes stream;
      SimTime now{};
      for (int piece = 0; piece < 40; ++piece) {
        Bytes bytes;
        switch (rng.uniform(0, 4)) {
          case 0:
            bytes = read(protocol, static_cast<std::uint8_t>(rng.uniform(0, 200)));
            break;
          case 1:
            bytes = ping_packet(protocol, 1);
            bytes.back() ^= 0x5A;
            break;
          case 2:
            bytes = wire::FrameFormat::for_protocol(protocol).header;
            bytes.insert(bytes.end(), {0x01, 0x00, 0x00});
            break;
          case 3:
            for (std::uint64_t n = rng.uniform(1, 9); n > 0; --n) {
              bytes.push_back(static_cast<std::uint8_t>(rng.uniform(0, 255)));
            }
            break;
          default:
            bytes = read(protocol, 7);
            bytes.resize(rng.uniform(1, bytes.size() - 1));
            break;
        }
        for (std::size_t at = 0; at < bytes.size();) {
          const std::size_t n = std::min<std::size_t>(rng.uniform(1, 6), bytes.size() - at);
          framer.feed(std::span(bytes).subspan(at, n), now, events);
          at += n;
          now += 10us;
        }
        stream.insert(stream.end(), bytes.begin(), bytes.end());
        if (rng.uniform(0, 3) == 0) {
          now += timeout * 2;
        }
      }
      framer.expire(now + timeout * 2, events);
      INFO(test::summary(events));
      REQUIRE(!events.empty());
      for (const auto& event : events) {
        CHECK(raw_of(event) == covered(stream, event));
        const std::string summary = test::summary({event});
        seen.insert(summary.substr(0, summary.find('(')));
      }
    }
    CHECK(seen ==
          std::set<std::string>{"bad_check", "frame", "garbage", "impossible_length", "truncated"});
  }
}
