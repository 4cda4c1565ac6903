#include "bus/usb_adapter_link.hpp"

#include <catch2/catch.hpp>
#include <numeric>

#include "bus_rig.hpp"

namespace dxlemu::test {
namespace {

using bus::LoopbackLink;
using bus::UsbAdapter;
using bus::UsbAdapterLink;
using std::chrono::microseconds;
using std::chrono::milliseconds;

constexpr std::uint32_t kMbit = 1'000'000;  // 10 us a byte
constexpr UsbAdapter kFt232r{milliseconds(16), bus::kFullSpeedPacketData};

sim::SimTime at_us(std::int64_t us) {
  return sim::SimTime{microseconds(us)};
}

// `n` bytes counting up from `first`, standing for one status packet.
std::vector<std::uint8_t> bytes_from(std::uint8_t first, std::size_t n) {
  std::vector<std::uint8_t> out(n);
  std::iota(out.begin(), out.end(), first);
  return out;
}

// An adapter on a hand-advanced clock, and what reaches the client behind it.
struct AdapterRig {
  sim::Scheduler scheduler;
  LoopbackLink client;
  UsbAdapterLink adapter;

  explicit AdapterRig(UsbAdapter settings) : adapter(scheduler, client, settings) {}
  // The bus hands over `bytes` at `at`, the moment their last byte arrived.
  void status(const std::vector<std::uint8_t>& bytes, sim::SimTime at) {
    scheduler.advance_to(at);
    CHECK(adapter.deliver(bytes, at, kMbit));
  }
};

TEST_CASE("A short reply reaches the client when the latency timer next expires", "[adapter]") {
  AdapterRig rig(kFt232r);
  const auto reply = bytes_from(0, 14);
  rig.status(reply, at_us(3'000));
  rig.scheduler.advance_to(at_us(16'000) - sim::SimDuration{1});
  CHECK(rig.client.deliveries().empty());
  rig.scheduler.advance_to(at_us(16'000));
  CHECK(rig.client.deliveries() == std::vector<LoopbackLink::Delivery>{{reply, at_us(16'000)}});
}

TEST_CASE("The latency timer counts from the chip's last USB packet, empty ones included",
          "[adapter]") {
  AdapterRig rig(kFt232r);
  // Idle, the chip sent status packets at 16 and 32 ms: the timer expires next at 48 ms.
  rig.status(bytes_from(0, 14), at_us(40'000));
  // The packet at 48 ms restarts it: 64 ms next, then 80 ms (an empty packet at 64).
  rig.status(bytes_from(20, 14), at_us(50'000));
  rig.status(bytes_from(40, 14), at_us(70'000));
  // A byte arriving as the timer expires waits for the next expiry.
  rig.status(bytes_from(60, 1), at_us(96'000));
  rig.scheduler.advance_to(at_us(200'000));
  CHECK(rig.client.deliveries() == std::vector<LoopbackLink::Delivery>{
                                       {bytes_from(0, 14), at_us(48'000)},
                                       {bytes_from(20, 14), at_us(64'000)},
                                       {bytes_from(40, 14), at_us(80'000)},
                                       {bytes_from(60, 1), at_us(112'000)},
                                   });
}

TEST_CASE("A burst longer than a USB packet goes on in packets of the chip's data size",
          "[adapter]") {
  AdapterRig rig(kFt232r);
  // A chained read of five servos: 14-byte statuses back to back from 1 ms on, each handed over
  // as its last byte arrives (every 140 us).
  std::vector<std::uint8_t> all;
  for (int s = 0; s < 5; ++s) {
    const auto status = bytes_from(static_cast<std::uint8_t>(14 * s), 14);
    all.insert(all.end(), status.begin(), status.end());
    rig.status(status, at_us(1'000 + 140 * (s + 1)));
  }
  rig.scheduler.advance_to(at_us(100'000));
  const auto& got = rig.client.deliveries();
  REQUIRE(got.size() == 2);
  // The 62nd byte (the 6th of the fifth status) filled the packet at 1'000 + 4 x 140 + 60 us;
  // the chip sends it then, and dxlemu as soon as the bus hands that status over.
  CHECK(got[0] == LoopbackLink::Delivery{{all.begin(), all.begin() + 62}, at_us(1'700)});
  // The full packet restarted the timer: the other 8 bytes go 16 ms after it.
  CHECK(got[1] == LoopbackLink::Delivery{{all.begin() + 62, all.end()}, at_us(1'620 + 16'000)});
}

TEST_CASE("A high-speed chip (U2D2) fills a packet only after 510 bytes", "[adapter]") {
  AdapterRig rig({milliseconds(16), bus::kHighSpeedPacketData});
  const auto burst = bytes_from(0, 200);
  rig.status(burst, at_us(5'000));
  rig.status(burst, at_us(7'000));
  rig.status(burst, at_us(9'000));
  rig.scheduler.advance_to(at_us(100'000));
  const auto& got = rig.client.deliveries();
  REQUIRE(got.size() == 2);
  CHECK(got[0].bytes.size() == 510);
  CHECK(got[0].at == at_us(9'000));
  CHECK(got[1].bytes.size() == 90);
  // Byte 510, the 110th of the third burst, arrived 90 byte times before its last: the timer
  // restarted then.
  CHECK(got[1].at == at_us(9'000 - 900 + 16'000));
}

TEST_CASE("Bytes on the line while the timer sent a packet follow it at once", "[adapter]") {
  AdapterRig rig(kFt232r);
  rig.status(bytes_from(0, 14), at_us(10'000));
  // The next status ends at 16.05 ms: its first 8 bytes arrived before the expiry at 16 ms, so
  // on a real chip they went with it; dxlemu learns of them at 16.05 ms and sends them then.
  rig.status(bytes_from(14, 14), at_us(16'050));
  rig.scheduler.advance_to(at_us(100'000));
  CHECK(rig.client.deliveries() == std::vector<LoopbackLink::Delivery>{
                                       {bytes_from(0, 14), at_us(16'000)},
                                       {bytes_from(14, 8), at_us(16'050)},
                                       {bytes_from(22, 6), at_us(32'000)},
                                   });
}

TEST_CASE("A packet the client does not read is counted by the adapter", "[adapter]") {
  AdapterRig rig(kFt232r);
  rig.client.set_accepting(false);
  rig.status(bytes_from(0, 14), at_us(1'000));  // the chip takes it: deliver() says true
  rig.scheduler.advance_to(at_us(16'000));
  CHECK(rig.client.deliveries().empty());
  CHECK(rig.adapter.unread_drops() == 1);
}

TEST_CASE("With no latency the adapter passes every delivery straight through", "[adapter]") {
  AdapterRig rig({sim::SimDuration::zero(), bus::kFullSpeedPacketData});
  rig.status(bytes_from(0, 100), at_us(1'000));
  CHECK(rig.client.deliveries() ==
        std::vector<LoopbackLink::Delivery>{{bytes_from(0, 100), at_us(1'000)}});
  rig.client.set_accepting(false);
  CHECK_FALSE(rig.adapter.deliver(bytes_from(0, 1), at_us(1'000), kMbit));
}

// A bus behind the adapter, as the daemon builds a port with --adapter-latency-ms.
struct AdaptedBus {
  sim::Scheduler scheduler;
  LoopbackLink client;
  UsbAdapterLink adapter{scheduler, client, kFt232r};
  bus::Bus bus{scheduler, adapter};
};

TEST_CASE("A ping's status waits for the timer after its modelled time", "[adapter]") {
  AdaptedBus rig;
  rig.bus.add_servo(std::make_unique<model::Servo>(shipped_model("xm430-w350"), 1));
  rig.scheduler.advance_to(at_us(20'000));
  const auto ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  rig.bus.receive(ping, rig.scheduler.now(), BusRig::kBaud);
  rig.scheduler.advance_to(at_us(100'000));
  REQUIRE(rig.client.deliveries().size() == 1);
  CHECK(rig.client.deliveries()[0].bytes.size() == 14);
  CHECK(rig.client.deliveries()[0].at == at_us(32'000));
  CHECK(rig.bus.stats().replies == 1);
}

TEST_CASE("Under immediate reply timing the latency still applies, in simulated time",
          "[adapter]") {
  AdaptedBus rig;
  rig.bus.set_reply_timing(bus::ReplyTiming::Immediate);
  rig.bus.add_servo(std::make_unique<model::Servo>(shipped_model("xm430-w350"), 1));
  const auto ping = wire::encode_instruction({wire::Protocol::V2, 1, wire::Ping{}});
  rig.bus.receive(ping, rig.scheduler.now(), BusRig::kBaud);
  rig.scheduler.run_due();
  CHECK(rig.client.deliveries().empty());
  rig.scheduler.advance_to(at_us(16'000));
  REQUIRE(rig.client.deliveries().size() == 1);
  CHECK(rig.client.deliveries()[0].at == at_us(16'000));
}

}  // namespace
}  // namespace dxlemu::test
