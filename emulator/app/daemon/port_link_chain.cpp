#include "app/daemon/port_link_chain.hpp"

#include <chrono>

#include "app/daemon/log.hpp"

namespace dxlemu::app {
namespace {

// The USB serial adapter in front of `port`: its own settings, else the command line's. None
// under fast timing, whose replies come at once (docs/timing.md "USB adapter latency").
bus::UsbAdapter usb_adapter(const PortConfig& port, const RunOptions& options) {
  const int latency_ms = port.adapter_latency_ms.value_or(options.adapter_latency_ms);
  const std::string chip = port.adapter_chip.value_or(options.adapter_chip);
  if (latency_ms == 0 || options.timing == TimingMode::Fast) {
    return {};
  }
  return {std::chrono::milliseconds(latency_ms), adapter_packet_data(chip).value()};
}

}  // namespace

PortLinkChain::PortLinkChain(bus::ByteLink& client, sim::Scheduler& scheduler,
                             bus::LateReplyGuard::Clock wall_now, const PortConfig& port,
                             const RunOptions& options)
    : bus_side_(&client) {
  if (options.timing != TimingMode::Manual) {
    // Under manual timing simulated time is not the wall clock's: nothing can be late.
    bus::LateReplyPolicy policy;
    policy.drop_after = options.late_reply_limit;
    guard_ = std::make_unique<bus::LateReplyGuard>(*bus_side_, std::move(wall_now), policy,
                                                   [name = port.name](const std::string& message) {
                                                     log(LogLevel::Warn, name + ": " + message);
                                                   });
    bus_side_ = guard_.get();
  }
  // The adapter before the guard: the guard measures when the adapter's USB packets go out.
  if (const bus::UsbAdapter usb = usb_adapter(port, options);
      usb.latency > sim::SimDuration::zero()) {
    adapter_ = std::make_unique<bus::UsbAdapterLink>(scheduler, *bus_side_, usb);
    adapter_chip_ = port.adapter_chip.value_or(options.adapter_chip);
    bus_side_ = adapter_.get();
  } else if (options.timing == TimingMode::Fast &&
             port.adapter_latency_ms.value_or(options.adapter_latency_ms) != 0) {
    log(LogLevel::Warn, port.name + ": no USB adapter latency under --timing fast");
  }
}

nlohmann::json PortLinkChain::adapter_info() const {
  if (!adapter_) {
    return {{"latency_ms", 0}};
  }
  const bus::UsbAdapter& usb = adapter_->adapter();
  return {
      {"latency_ms", std::chrono::duration_cast<std::chrono::milliseconds>(usb.latency).count()},
      {"chip", adapter_chip_},
      {"packet_data_bytes", usb.packet_data},
      {"unread_drops", adapter_->unread_drops()}};
}

std::string PortLinkChain::lateness_summary() const {
  if (!guard_) {
    return "";
  }
  const bus::LatenessSummary l = guard_->summary();
  return ", " + std::to_string(l.over[0]) + " replies more than " +
         std::to_string(bus::LatenessSummary::kThresholds[0].count()) + " ms late (at most " +
         std::to_string(std::chrono::duration_cast<std::chrono::microseconds>(l.max).count()) +
         " us), " + std::to_string(l.dropped) + " dropped as late";
}

}  // namespace dxlemu::app
