// Garbage before, between and after packets; failed headers are rescanned from the next byte so
// that no packet starting inside rejected bytes is lost; partial packets time out.
#include <catch2/catch.hpp>

#include "framer_events.hpp"
#include "golden_file.hpp"
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

std::string frame_all(Protocol protocol, const Bytes& stream) {
  Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  framer.expire(SimTime{} + 1s, events);
  return test::summary(events);
}

// Garbage that is full of header prefixes but never a whole header of either protocol.
const Bytes kTrickyGarbage = {0x00, 0xFF, 0x12, 0xFF, 0xFF, 0xFD, 0xFD, 0xFF, 0x55, 0xFD, 0xFF};

}  // namespace

TEST_CASE("Garbage before, between and after golden packets is skipped and counted",
          "[wire][garbage]") {
  for (const auto protocol : {Protocol::V1, Protocol::V2}) {
    const auto packets = test::load_golden_packets(protocol);
    const Bytes junk = {0x13, 0x37, 0x00, 0xFE};
    Bytes stream = junk;
    for (const auto& p : packets) {
      stream.insert(stream.end(), p.bytes.begin(), p.bytes.end());
      stream.insert(stream.end(), junk.begin(), junk.end());
    }
    Framer framer(protocol);
    std::vector<wire::FramerEvent> events;
    framer.feed(stream, SimTime{}, events);
    const auto frames = test::frames_of(events);
    REQUIRE(frames.size() == packets.size());
    for (std::size_t i = 0; i < packets.size(); ++i) {
      CHECK(frames[i].raw == packets[i].bytes);
    }
    std::size_t garbage = 0;
    for (const auto& e : test::errors_of(events)) {
      CHECK(e.kind == wire::FramingErrorKind::Garbage);
      garbage += e.bytes;
    }
    CHECK(garbage == junk.size() * (packets.size() + 1));
  }
}

TEST_CASE("Garbage full of header prefixes does not hide the packet after it", "[wire][garbage]") {
  CHECK(frame_all(Protocol::V2, concat({kTrickyGarbage, ping_packet(Protocol::V2, 7)})) ==
        "garbage(11) frame(id=7)");
  // In 1.0 FF FF is a whole header: FF FF FD and FF FF FF are headers with invalid lengths or IDs.
  const Bytes v1_garbage = {0x00, 0xFF, 0x12, 0xFE, 0x55, 0xFF};
  CHECK(frame_all(Protocol::V1, concat({v1_garbage, ping_packet(Protocol::V1, 7)})) ==
        "garbage(6) frame(id=7)");
}

TEST_CASE("A 1.0 run of FF bytes before a packet resynchronises on the last FF FF",
          "[wire][garbage]") {
  // FF FF FF FF FF 03 ...: each FF FF followed by FF is a header with the invalid ID 0xFF.
  CHECK(frame_all(Protocol::V1, concat({{0xFF, 0xFF, 0xFF}, ping_packet(Protocol::V1, 3)})) ==
        "garbage(3) frame(id=3)");
}

TEST_CASE("A header with an invalid Packet ID is garbage and rescanning continues",
          "[wire][garbage]") {
  // 0xFD and 0xFF are not Packet IDs in 2.0 (0 ~ 252 and 0xFE).
  const Bytes bad_id = {0xFF, 0xFF, 0xFD, 0x00, 0xFD, 0x03, 0x00};
  CHECK(frame_all(Protocol::V2, concat({bad_id, ping_packet(Protocol::V2, 1)})) ==
        "garbage(7) frame(id=1)");
}

TEST_CASE("A bad CRC is reported with the unverified ID and a packet inside it is still found",
          "[wire][garbage]") {
  // A header announcing 13 bytes (LENGTH 13) swallows a whole ping; its CRC cannot match, and the
  // rescan from the next byte finds the ping.
  Bytes stream = {0xFF, 0xFF, 0xFD, 0x00, 0x05, 0x0D, 0x00};
  const Bytes inner = ping_packet(Protocol::V2, 9);
  stream.insert(stream.end(), inner.begin(), inner.end());
  stream.insert(stream.end(), {0x11, 0x22, 0x33});
  Framer framer(Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  CHECK(test::summary(events) == "bad_check(id=5) frame(id=9)");
  const auto error = test::errors_of(events).at(0);
  CHECK(error.bytes == stream.size());
  CHECK(error.instruction == std::optional<std::uint8_t>(0xFF));
}

TEST_CASE("A 1.0 packet with a wrong checksum is reported and the next packet still frames",
          "[wire][garbage]") {
  Bytes corrupt = ping_packet(Protocol::V1, 4);
  corrupt.back() ^= 0x01;
  CHECK(frame_all(Protocol::V1, concat({corrupt, ping_packet(Protocol::V1, 5)})) ==
        "bad_check(id=4) frame(id=5)");
}

TEST_CASE("An impossible LENGTH is rejected at once instead of swallowing what follows",
          "[wire][garbage]") {
  const Bytes too_short = {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x02, 0x00};  // LENGTH 2 < 3
  const Bytes too_long = {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0xFF, 0xFF};   // LENGTH 65535
  for (const auto& header : {too_short, too_long}) {
    Framer framer(Protocol::V2);
    std::vector<wire::FramerEvent> events;
    framer.feed(concat({header, ping_packet(Protocol::V2, 2)}), SimTime{}, events);
    CHECK(test::summary(events) == "impossible_length(id=1) frame(id=2)");
  }
  const Bytes v1_too_short = {0xFF, 0xFF, 0x01, 0x01};  // LENGTH 1 < 2
  CHECK(frame_all(Protocol::V1, concat({v1_too_short, ping_packet(Protocol::V1, 2)})) ==
        "impossible_length(id=1) frame(id=2)");
}

TEST_CASE("A partial packet is dropped after the 2.0 inter-byte timeout of 1.5 ms",
          "[wire][timeout]") {
  const Bytes p = ping_packet(Protocol::V2, 1);
  const std::span<const std::uint8_t> bytes(p);
  SECTION("a gap of exactly 1.5 ms is still one packet") {
    Framer framer(Protocol::V2);
    std::vector<wire::FramerEvent> events;
    framer.feed(bytes.first(4), SimTime{}, events);
    framer.feed(bytes.subspan(4), SimTime{} + 1500us, events);
    CHECK(test::summary(events) == "frame(id=1)");
  }
  SECTION("a longer gap truncates the partial packet and the new bytes start afresh") {
    Framer framer(Protocol::V2);
    std::vector<wire::FramerEvent> events;
    framer.feed(bytes.first(6), SimTime{}, events);
    REQUIRE(framer.deadline() == SimTime{} + 1500us + sim::SimDuration{1});
    framer.feed(bytes.subspan(6), SimTime{} + 1501us, events);
    framer.feed(p, SimTime{} + 1600us, events);
    CHECK(test::summary(events) == "truncated(6) garbage(4) frame(id=1)");
    CHECK(test::errors_of(events).at(0).id == std::optional<std::uint8_t>(1));
  }
  SECTION("expire() drops the partial packet without new bytes") {
    Framer framer(Protocol::V2);
    std::vector<wire::FramerEvent> events;
    framer.feed(bytes.first(8), SimTime{}, events);
    framer.expire(SimTime{} + 1500us, events);
    CHECK(events.empty());
    framer.expire(SimTime{} + 1501us, events);
    CHECK(test::summary(events) == "truncated(8)");
    CHECK(framer.buffered() == 0);
    CHECK(!framer.deadline());
  }
}

TEST_CASE("A partial 1.0 packet survives gaps up to 100 ms and is dropped after",
          "[wire][timeout]") {
  const Bytes p = ping_packet(Protocol::V1, 1);
  const std::span<const std::uint8_t> bytes(p);
  Framer framer(Protocol::V1);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes.first(3), SimTime{}, events);
  framer.feed(bytes.subspan(3), SimTime{} + 100ms, events);
  CHECK(test::summary(events) == "frame(id=1)");
  events.clear();
  framer.feed(bytes.first(3), SimTime{} + 200ms, events);
  framer.expire(SimTime{} + 300ms + sim::SimDuration{1}, events);
  CHECK(test::summary(events) == "truncated(3)");
}

TEST_CASE("A timed-out header that swallowed a whole packet gives that packet back",
          "[wire][timeout]") {
  // LENGTH 100 is possible, so the framer waits; when the line goes quiet, the rescan finds the
  // complete ping that arrived inside the announced length.
  Bytes stream = {0xFF, 0xFF, 0xFD, 0x00, 0x03, 0x64, 0x00};
  const Bytes inner = ping_packet(Protocol::V2, 6);
  stream.insert(stream.end(), inner.begin(), inner.end());
  Framer framer(Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(stream, SimTime{}, events);
  CHECK(events.empty());
  framer.expire(SimTime{} + 2ms, events);
  CHECK(test::summary(events) == "truncated(17) frame(id=6)");
  const auto frame = test::frames_of(events).at(0);
  CHECK(frame.first_byte_at == SimTime{});  // the time the bytes arrived, not the timeout
}

TEST_CASE("A lone header prefix at a timeout is garbage, a started packet is truncated",
          "[wire][timeout]") {
  Framer framer(Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(Bytes{0xFF, 0xFF, 0xFD}, SimTime{}, events);
  framer.expire(SimTime{} + 2ms, events);
  CHECK(test::summary(events) == "garbage(3)");
}

TEST_CASE("The 1.0 framer hears a 2.0 packet as noise, not as an impossible 1.0 packet",
          "[wire][garbage]") {
  // FF FF FD 00 reads as 1.0 ID 0xFD with LENGTH 0: on a mixed bus that is the other protocol.
  const Bytes v2_read = wire::encode_instruction({Protocol::V2, 1, wire::Read{132, 4}});
  CHECK(frame_all(Protocol::V1, concat({v2_read, ping_packet(Protocol::V1, 2)})) ==
        "garbage(" + std::to_string(v2_read.size()) + ") frame(id=2)");
}
