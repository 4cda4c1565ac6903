// PortLinkChain: which links stand between a port's bus and its client under each timing mode
// (docs/timing.md "Late replies", "USB adapter latency").
#include <catch2/catch.hpp>

#include "app/daemon/port_link_chain.hpp"
#include "bus/loopback_link.hpp"

using namespace dxlemu;
using namespace std::chrono_literals;

namespace {

const std::vector<std::uint8_t> kReply = {0xFF, 0xFF, 0xFD, 0x00, 0x01};
constexpr std::uint32_t kBps = 1'000'000;

// A port's client and the clocks its chain runs on; the wall clock is set by hand.
struct ChainRig {
  sim::Scheduler scheduler;
  bus::LoopbackLink client;
  sim::SimTime wall{};
  app::PortConfig port{"dxl0", std::nullopt, {}, {}, {}, {}, {}, {}};

  app::PortLinkChain chain(const app::RunOptions& options) {
    return {client, scheduler, [this] { return wall; }, port, options};
  }
};

app::RunOptions timing(app::TimingMode mode) {
  app::RunOptions options;
  options.timing = mode;
  return options;
}

}  // namespace

TEST_CASE("Under manual timing the bus writes straight to the client", "[app][links]") {
  ChainRig rig;
  app::RunOptions options = timing(app::TimingMode::Manual);
  auto chain = rig.chain(options);
  CHECK(&chain.bus_side() == &rig.client);
  CHECK(chain.guard() == nullptr);
  CHECK(chain.adapter() == nullptr);
  CHECK(chain.adapter_info() == nlohmann::json{{"latency_ms", 0}});
  CHECK(chain.lateness_summary().empty());
}

TEST_CASE("Under realtime timing a reply later than the limit is dropped by the guard",
          "[app][links]") {
  ChainRig rig;
  app::RunOptions options = timing(app::TimingMode::Realtime);
  options.late_reply_limit = 20ms;
  auto chain = rig.chain(options);
  REQUIRE(chain.guard() != nullptr);
  CHECK(chain.adapter() == nullptr);
  rig.wall = sim::SimTime{} + 1ms;
  CHECK(chain.bus_side().deliver(kReply, sim::SimTime{}, kBps));
  rig.wall = sim::SimTime{} + 50ms;
  CHECK(chain.bus_side().deliver(kReply, sim::SimTime{} + 10ms,
                                 kBps));  // dropped counts as delivered
  CHECK(rig.client.deliveries().size() == 1);
  CHECK(chain.guard()->summary().dropped == 1);
  CHECK(chain.lateness_summary() ==
        ", 1 replies more than 1 ms late (at most 40000 us), 1 dropped as late");
}

TEST_CASE("An adapter latency puts a USB adapter before the guard, the port's own settings first",
          "[app][links]") {
  ChainRig rig;
  app::RunOptions options = timing(app::TimingMode::Realtime);
  options.adapter_latency_ms = 4;
  rig.port.adapter_latency_ms = 16;
  rig.port.adapter_chip = "ft232r";
  auto chain = rig.chain(options);
  REQUIRE(chain.adapter() != nullptr);
  REQUIRE(chain.guard() != nullptr);
  CHECK(&chain.bus_side() == chain.adapter());
  CHECK(chain.adapter_info() == nlohmann::json{{"latency_ms", 16},
                                               {"chip", "ft232r"},
                                               {"packet_data_bytes", bus::kFullSpeedPacketData},
                                               {"unread_drops", 0}});
  // A short reply waits in the adapter for its latency timer, then goes through the guard.
  chain.bus_side().deliver(kReply, sim::SimTime{}, kBps);
  CHECK(rig.client.deliveries().empty());
  rig.scheduler.advance_by(16ms);
  rig.wall = rig.scheduler.now();
  REQUIRE(rig.client.deliveries().size() == 1);
  CHECK(rig.client.deliveries()[0].at == sim::SimTime{} + 16ms);
  CHECK(chain.guard()->summary().deliveries == 1);
}

TEST_CASE("Fast timing has no adapter latency, whatever the options say", "[app][links]") {
  ChainRig rig;
  app::RunOptions options = timing(app::TimingMode::Fast);
  options.adapter_latency_ms = 16;
  auto chain = rig.chain(options);
  CHECK(chain.adapter() == nullptr);
  CHECK(chain.guard() != nullptr);
  CHECK(chain.adapter_info() == nlohmann::json{{"latency_ms", 0}});
}
