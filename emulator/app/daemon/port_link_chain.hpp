#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "app/config/bus_config.hpp"
#include "app/daemon/run_options.hpp"
#include "bus/byte_link.hpp"
#include "bus/late_reply_guard.hpp"
#include "bus/usb_adapter_link.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::app {

/// The links between one port's bus and its client, as the run options ask for them:
///
///   bus -> USB adapter (--adapter-latency-ms, not under fast timing)
///       -> late-reply guard (realtime and fast timing) -> the client's link (the PTY)
///
/// The adapter sits before the guard so that the guard measures when the adapter's USB packets
/// go out. Under manual timing simulated time is not the wall clock's, so nothing can be late
/// and there is no guard. Only a composition: each link is its own type in bus/.
class PortLinkChain {
 public:
  /// The chain for `port` over `client` (the PTY; it must outlive the chain), its adapter's
  /// timer on `scheduler`, the guard's present read from `wall_now` (the driver's wall clock on
  /// the scheduler's scale). Warns when --timing fast leaves out an adapter the config asks for.
  PortLinkChain(bus::ByteLink& client, sim::Scheduler& scheduler,
                bus::LateReplyGuard::Clock wall_now, const PortConfig& port,
                const RunOptions& options);

  /// Where the port's bus sends its bytes: the first link of the chain.
  bus::ByteLink& bus_side() { return *bus_side_; }
  /// The late-reply guard, or null under manual timing.
  bus::LateReplyGuard* guard() const { return guard_.get(); }
  /// The USB adapter, or null when there is none.
  bus::UsbAdapterLink* adapter() const { return adapter_.get(); }
  /// The adapter as `list` reports it (docs/control-api.md): {"latency_ms": 0} without one, else
  /// its latency, chip, USB packet data bytes and the packets the client did not read.
  nlohmann::json adapter_info() const;
  /// One clause for the port's summary at exit: replies over 1 ms late, the latest, and those
  /// dropped as late, starting with ", "; empty without a guard.
  std::string lateness_summary() const;

 private:
  std::unique_ptr<bus::LateReplyGuard> guard_;
  std::unique_ptr<bus::UsbAdapterLink> adapter_;
  std::string adapter_chip_;
  bus::ByteLink* bus_side_;
};

}  // namespace dxlemu::app
