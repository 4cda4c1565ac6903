// TraceFanOut: every packet each way to the trace file, the capture and the control API's trace
// subscribers of its port (docs/trace.md, docs/pcap.md, docs/control-api.md "Trace events").
#include <catch2/catch.hpp>
#include <sstream>

#include "app/daemon/trace_fan_out.hpp"
#include "app/record/trace_record.hpp"
#include "pcap_layout.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;

namespace {

constexpr std::chrono::microseconds kTraceStart{1'700'000'000'000'000};
using test::pcap::kGlobalHeaderBytes;
using test::pcap::kRecordHeaderBytes;

const std::vector<std::uint8_t> kRead =
    wire::encode_instruction({wire::Protocol::V2, 1, wire::Read{132, 4}});
const std::vector<std::uint8_t> kStatus =
    wire::encode_status({wire::Protocol::V2, 1, 0, {0xFC, 0x03, 0x2D, 0x00}});

wire::FramerEvent heard(sim::SimTime at) {
  wire::Framer framer(wire::Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(kRead, at, events);
  REQUIRE(events.size() == 1);
  return events[0];
}

// A connection that keeps the events sent to it.
struct Client {
  std::vector<std::string> events;
  control::Connection connection(std::uint64_t id) {
    return {id, [this](const std::string& line) { events.push_back(line); }};
  }
};

// The trace event of a trace record: the same members after "event".
std::string event_of(const std::string& record) {
  return R"({"event":"trace",)" + record.substr(1);
}

}  // namespace

TEST_CASE("Every packet each way is a line of the trace file, flushed when the handler ends",
          "[app][trace]") {
  auto file = std::make_unique<std::ostringstream>();
  std::ostringstream& trace = *file;
  app::TraceFanOut fan_out(std::move(file), nullptr, kTraceStart);
  const bus::LineObserver dxl0 = fan_out.observer("dxl0", 0);
  dxl0.heard(heard(sim::SimTime{} + 1ms));
  dxl0.sent(kStatus, sim::SimTime{} + 2ms, wire::Protocol::V2);
  fan_out.flush();
  CHECK(trace.str() ==
        app::heard_record("dxl0", heard(sim::SimTime{} + 1ms)) + "\n" +
            app::sent_record("dxl0", kStatus, sim::SimTime{} + 2ms, wire::Protocol::V2) + "\n");
}

TEST_CASE("A subscriber gets the trace events of its port or of every port until it leaves",
          "[app][trace]") {
  app::TraceFanOut fan_out(nullptr, nullptr, kTraceStart);
  const bus::LineObserver dxl0 = fan_out.observer("dxl0", 0);
  const bus::LineObserver arm = fan_out.observer("arm", 1);
  Client one;
  Client all;
  fan_out.subscribe(one.connection(1), {"arm"});
  fan_out.subscribe(all.connection(2), {});
  dxl0.heard(heard(sim::SimTime{}));
  arm.sent(kStatus, sim::SimTime{} + 1ms, wire::Protocol::V2);
  CHECK(one.events == std::vector<std::string>{event_of(app::sent_record(
                          "arm", kStatus, sim::SimTime{} + 1ms, wire::Protocol::V2))});
  CHECK(all.events.size() == 2);
  CHECK(all.events[0] == event_of(app::heard_record("dxl0", heard(sim::SimTime{}))));

  // A new subscription of the same connection replaces the old one; a closed one gets nothing.
  fan_out.subscribe(one.connection(1), {"dxl0"});
  fan_out.unsubscribe(2);
  arm.sent(kStatus, sim::SimTime{} + 2ms, wire::Protocol::V2);
  dxl0.sent(kStatus, sim::SimTime{} + 3ms, wire::Protocol::V2);
  CHECK(one.events.size() == 2);
  CHECK(one.events[1].find(R"("port":"dxl0")") != std::string::npos);
  CHECK(all.events.size() == 2);
  fan_out.unsubscribe(7);  // none: nothing happens
}

TEST_CASE("With a wall clock, each out record says how late it went out, never early",
          "[app][trace]") {
  auto file = std::make_unique<std::ostringstream>();
  std::ostringstream& trace = *file;
  app::TraceFanOut fan_out(std::move(file), nullptr, kTraceStart);
  sim::SimTime wall = sim::SimTime{} + 2500us;
  const bus::LineObserver dxl0 = fan_out.observer("dxl0", 0, [&wall] { return wall; });
  dxl0.heard(heard(sim::SimTime{} + 1ms));
  dxl0.sent(kStatus, sim::SimTime{} + 2ms, wire::Protocol::V2);
  wall = sim::SimTime{} + 1ms;  // the wall clock behind the modelled time: not late
  dxl0.sent(kStatus, sim::SimTime{} + 3ms, wire::Protocol::V2);
  fan_out.flush();
  CHECK(trace.str() ==
        app::heard_record("dxl0", heard(sim::SimTime{} + 1ms)) + "\n" +
            app::sent_record("dxl0", kStatus, sim::SimTime{} + 2ms, wire::Protocol::V2, 500us) +
            "\n" +
            app::sent_record("dxl0", kStatus, sim::SimTime{} + 3ms, wire::Protocol::V2, 0us) +
            "\n");
}

TEST_CASE("The capture gets one record per packet, stamped with its port's index", "[app][trace]") {
  auto file = std::make_unique<std::ostringstream>();
  std::ostringstream& capture = *file;
  app::TraceFanOut fan_out(nullptr, std::move(file), kTraceStart);
  CHECK(capture.str().size() == kGlobalHeaderBytes);
  const bus::LineObserver arm = fan_out.observer("arm", 1);
  arm.heard(heard(sim::SimTime{}));
  arm.sent(kStatus, sim::SimTime{} + 1ms, wire::Protocol::V2);
  const std::string bytes = capture.str();
  const std::size_t first = kGlobalHeaderBytes + kRecordHeaderBytes;
  const std::size_t second =
      first + app::kPcapPseudoHeaderBytes + kRead.size() + kRecordHeaderBytes;
  REQUIRE(bytes.size() == second + app::kPcapPseudoHeaderBytes + kStatus.size());
  // Pseudo-header: version, direction, protocol, port index.
  CHECK(bytes[first + 1] == static_cast<char>(app::PcapDirection::ToServos));
  CHECK(bytes[first + 3] == 1);
  CHECK(bytes[second + 1] == static_cast<char>(app::PcapDirection::ToClient));
  CHECK(bytes[second + 3] == 1);
}

TEST_CASE("A trace or capture file that cannot be created is refused naming its option",
          "[app][trace]") {
  CHECK_THROWS_WITH(
      app::TraceFanOut::open("/nonexistent-dir/trace.jsonl", std::nullopt, kTraceStart),
      Catch::Contains("/nonexistent-dir/trace.jsonl") &&
          Catch::Contains("cannot be created (--trace)"));
  CHECK_THROWS_WITH(app::TraceFanOut::open(std::nullopt, "/nonexistent-dir/x.pcap", kTraceStart),
                    Catch::Contains("cannot be created (--pcap)"));
  CHECK(app::TraceFanOut::open(std::nullopt, std::nullopt, kTraceStart) != nullptr);
}
