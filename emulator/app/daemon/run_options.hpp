#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/web_address.hpp"
#include "bus/late_reply_guard.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::app {

/// How simulated time relates to the wall clock (`--timing`, docs/timing.md).
enum class TimingMode {
  Realtime,  ///< replies when real servos would send them (the default)
  Fast,      ///< replies at once: no wire time, processing or Return Delay Time
  Manual,    ///< simulated time stands still until the control API steps it; replies at once
};

/// What `dxlemu run` does besides serving the buses.
struct RunOptions {
  TimingMode timing = TimingMode::Realtime;
  /// Keep every servo's EEPROM here across restarts (docs/config.md "State file").
  std::optional<std::filesystem::path> state;
  /// Write every packet both ways here as JSON lines (docs/trace.md).
  std::optional<std::filesystem::path> trace;
  /// Write every packet both ways here as a pcap capture for Wireshark (docs/pcap.md).
  std::optional<std::filesystem::path> pcap;
  /// The control API's socket (docs/control-api.md); default: default_control_path().
  std::optional<std::filesystem::path> control;
  /// Serve the web interface here (docs/web.md); nullopt: no web interface.
  std::optional<WebAddress> web;
  /// Every web connection may only look: the web interface changes nothing (--web-read-only).
  bool web_read_only = false;
  /// The web interface's files (index.html, ...); default: shipped_web_dir().
  std::filesystem::path web_root;
  /// A scenario file whose steps start with simulated time (docs/faults.md "Scenarios").
  std::optional<std::filesystem::path> scenario;
  /// Where hand.play and --hand look up a trajectory by name (docs/hands.md "Shipped
  /// trajectories"), in order.
  std::vector<std::filesystem::path> trajectory_dirs;
  /// Seeds every random choice of fault injection (docs/faults.md).
  std::uint64_t seed = 1;
  /// Under realtime timing, how much earlier than dxlemu reads them the client's bytes count as
  /// written (docs/timing.md "PTY hand-over"); nullopt: measured at start.
  std::optional<sim::SimDuration> pty_handover;
  /// The motion model's tick period (docs/motion.md).
  sim::SimDuration tick = std::chrono::milliseconds(1);
  /// Under realtime and fast timing, replies later than this against their modelled time are
  /// dropped (docs/timing.md "Late replies"); zero never drops.
  sim::SimDuration late_reply_limit = bus::LateReplyPolicy{}.drop_after;
  /// SCHED_FIFO at this priority, and memory locked, where permitted (--realtime-priority).
  std::optional<int> realtime_priority;
  /// The USB serial adapter's latency timer in ms on every port without its own
  /// "adapter_latency_ms"; 0: no adapter (docs/timing.md "USB adapter latency").
  int adapter_latency_ms = 0;
  /// The adapter's chip on every port without its own "adapter_chip" (adapter_packet_data()).
  std::string adapter_chip = kDefaultAdapterChip;
};

/// The control socket used when --control is not given: dxlemu-PID.sock in $XDG_RUNTIME_DIR, or
/// in /tmp.
std::filesystem::path default_control_path();

}  // namespace dxlemu::app
