// Modbus RTU frames end at silences (modbus-rtu.md "RTU framing"): t3.5 ends a frame, a gap over
// t1.5 inside one breaks it; times come from the line's rate, on the virtual clock.
#include <catch2/catch.hpp>

#include "framer_events.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/rtu_timing.hpp"

namespace dxlemu::test::modbus_framer {

using namespace std::chrono_literals;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kBaud = 57600;
constexpr const wire::FrameShape& kShape = wire::traits(Protocol::Modbus).frame;

// Byte i of a write made at `at` starts i byte times (10 bits) later, as the bus stamps them.
std::vector<sim::SimTime> back_to_back(sim::SimTime at, std::size_t count, std::uint32_t bps) {
  std::vector<sim::SimTime> times;
  const std::int64_t byte_ns = (10'000'000'000 + bps - 1) / bps;
  for (std::size_t i = 0; i < count; ++i) {
    times.push_back(at + sim::SimDuration{byte_ns * static_cast<std::int64_t>(i)});
  }
  return times;
}

struct Line {
  wire::Framer framer{Protocol::Modbus};
  std::vector<wire::FramerEvent> events;
  sim::SimTime end{};  // when the last byte fed ends on the line

  explicit Line(std::uint32_t bps = kBaud) { framer.set_line_rate(bps); }
  void write(const Bytes& bytes, sim::SimTime at, std::uint32_t bps = kBaud) {
    const auto times = back_to_back(at, bytes.size(), bps);
    framer.feed(bytes, times, events);
    end = times.back() + sim::SimDuration{(10'000'000'000 + bps - 1) / bps};
  }
};

const Bytes kRead = wire::encode_modbus_frame(1, 0x03, Bytes{0x01, 0x1A, 0x00, 0x02});

TEST_CASE("t1.5 and t3.5 are 11-bit characters up to 19200 bit/s, fixed above", "[wire][modbus]") {
  // 3.5 x 11 bits at 9600 bit/s = 4.0104 ms; 1.5 x 11 bits = 1.71875 ms.
  CHECK(wire::frame_silence(kShape, 9600) == 4'010'417ns);
  CHECK(wire::frame_gap(kShape, 9600) == 1'718'750ns);
  CHECK(wire::frame_silence(kShape, 19200) == 2'005'209ns);
  CHECK(wire::frame_silence(kShape, 57600) == 1750us);
  CHECK(wire::frame_gap(kShape, 1'000'000) == 750us);
}

TEST_CASE("A Modbus frame is yielded once t3.5 of silence has followed it", "[wire][modbus]") {
  Line line;
  line.write(kRead, sim::SimTime{});
  CHECK(line.events.empty());  // no LENGTH: only the silence ends it
  REQUIRE(line.framer.deadline() == line.end + 1750us);
  line.framer.expire(line.end + 1750us - 1ns, line.events);
  CHECK(line.events.empty());
  line.framer.expire(line.end + 1750us, line.events);
  const auto frames = frames_of(line.events);
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].id == 1);
  CHECK(frames[0].instruction == 0x03);
  CHECK(frames[0].params == Bytes{0x01, 0x1A, 0x00, 0x02});
  CHECK(frames[0].raw == kRead);
  CHECK(!line.framer.deadline());
}

TEST_CASE("A frame written in pieces closer than t1.5 is one frame", "[wire][modbus]") {
  Line line;
  const Bytes head(kRead.begin(), kRead.begin() + 3);
  const Bytes tail(kRead.begin() + 3, kRead.end());
  line.write(head, sim::SimTime{});
  line.write(tail, line.end + 750us);  // exactly t1.5: still inside the frame
  line.framer.expire(line.end + 1750us, line.events);
  REQUIRE(frames_of(line.events).size() == 1);
  CHECK(frames_of(line.events)[0].raw == kRead);
}

TEST_CASE("A gap over t1.5 inside a frame makes it incomplete, and it is discarded",
          "[wire][modbus]") {
  Line line;
  const Bytes head(kRead.begin(), kRead.begin() + 3);
  const Bytes tail(kRead.begin() + 3, kRead.end());
  line.write(head, sim::SimTime{});
  line.write(tail, line.end + 751us);
  line.framer.expire(line.end + 1750us, line.events);
  CHECK(frames_of(line.events).empty());
  const auto errors = errors_of(line.events);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].kind == wire::FramingErrorKind::Truncated);
  CHECK(errors[0].bytes == kRead.size());
  CHECK(errors[0].id == 1);
}

TEST_CASE("Two frames separated by t3.5 are two, and closer they are one with a bad CRC",
          "[wire][modbus]") {
  Line apart;
  apart.write(kRead, sim::SimTime{});
  apart.write(kRead, apart.end + 1750us);
  apart.framer.expire(apart.end + 1750us, apart.events);
  CHECK(frames_of(apart.events).size() == 2);

  Line together;
  together.write(concat({kRead, kRead}), sim::SimTime{});
  together.framer.expire(together.end + 1750us, together.events);
  const auto errors = errors_of(together.events);
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].kind == wire::FramingErrorKind::BadCheck);
  CHECK(errors[0].bytes == 2 * kRead.size());
}

TEST_CASE("Frames too short, too long or with a bad CRC are refused, never yielded",
          "[wire][modbus]") {
  Line shorter;
  shorter.write({0x01, 0x03, 0x00}, sim::SimTime{});
  shorter.framer.end_of_write(shorter.events);
  REQUIRE(errors_of(shorter.events).size() == 1);
  CHECK(errors_of(shorter.events)[0].kind == wire::FramingErrorKind::Truncated);

  Line longer;
  longer.write(Bytes(300, 0x55), sim::SimTime{});
  CHECK(longer.framer.fed() == 300);
  longer.framer.end_of_write(longer.events);
  REQUIRE(errors_of(longer.events).size() == 1);
  CHECK(errors_of(longer.events)[0].kind == wire::FramingErrorKind::ImpossibleLength);
  CHECK(errors_of(longer.events)[0].bytes == 300);
  CHECK(longer.framer.fed() == 300);

  Bytes damaged = kRead;
  damaged[3] ^= 0x01;
  Line bad;
  bad.write(damaged, sim::SimTime{});
  bad.framer.end_of_write(bad.events);
  REQUIRE(errors_of(bad.events).size() == 1);
  CHECK(errors_of(bad.events)[0].kind == wire::FramingErrorKind::BadCheck);
}

TEST_CASE("At 9600 bit/s the silences are longer: 4.01 ms ends a frame", "[wire][modbus]") {
  Line line(9600);
  line.write(kRead, sim::SimTime{}, 9600);
  CHECK(line.framer.deadline() == line.end + 4'010'417ns);
  // A gap of 1.7 ms (under t1.5 = 1.72 ms) at 9600 bit/s keeps the frame whole.
  Line split(9600);
  split.write(Bytes(kRead.begin(), kRead.begin() + 4), sim::SimTime{}, 9600);
  split.write(Bytes(kRead.begin() + 4, kRead.end()), split.end + 1700us, 9600);
  split.framer.expire(split.end + 5ms, split.events);
  CHECK(frames_of(split.events).size() == 1);
}

}  // namespace dxlemu::test::modbus_framer
