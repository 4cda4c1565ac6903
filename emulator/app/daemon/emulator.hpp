#pragma once

#include <boost/asio/io_context.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/daemon/bus_state.hpp"
#include "app/record/pcap_writer.hpp"
#include "bus/late_reply_guard.hpp"
#include "control/api.hpp"
#include "control/target.hpp"
#include "io/control_server.hpp"
#include "io/cpu_wait.hpp"
#include "io/realtime_driver.hpp"
#include "physics/world_clock.hpp"
#include "sim/scheduler.hpp"

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
  /// A scenario file whose steps start with simulated time (docs/faults.md "Scenarios").
  std::optional<std::filesystem::path> scenario;
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

/// The running emulator: one io_context, one thread, a scheduler bound to the wall clock, a PTY
/// and a Bus per port, and the control socket. Construction opens everything or throws; nothing
/// runs half-configured. It is the control API's Target (docs/control-api.md).
class Emulator : public control::Target {
 public:
  /// Builds every port of `config` (already validated by parse_config or check_servo), restores
  /// EEPROM from the state file and opens the trace and the capture. Throws ConfigError for a bad
  /// state file, trace or capture path, std::system_error when a PTY or link cannot be made.
  Emulator(const ModelLibrary& library, const BusConfig& config, const RunOptions& options);
  ~Emulator() override;
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  // control::Target
  std::vector<std::string> port_names() const override;
  control::PortView* port(std::string_view name) override;
  nlohmann::json port_info(std::string_view port) const override;
  control::PhysicsView* physics() override { return physics_view_ ? &*physics_view_ : nullptr; }
  sim::SimTime now() const override;
  bool manual_clock() const override;
  void step_clock(sim::SimDuration d) override;
  void request_shutdown() override;
  faults::Injector& faults() override { return injector_; }
  void subscribe_trace(std::uint64_t client, std::vector<std::string> ports) override;
  void unsubscribe_trace(std::uint64_t client) override;
  void schedule_in(sim::SimDuration delay, std::function<void()> action) override;
  void warn(const std::string& message) override;

  /// Writes one readiness line per port (JSON) to `out`, serves until SIGINT or SIGTERM, then
  /// saves the state and returns; the destructor removes the links.
  void run(std::ostream& out);

 private:
  struct Port;
  void restore(const BusState& state);
  /// Writes one trace record of `port` (a JSON object on one line) to the trace file and to the
  /// subscribers of that port.
  void trace(const std::string& port, const std::string& line);
  /// What every I/O handler does last: flushes the trace file and saves the state if it changed.
  void finish_handler();
  /// Saves the state file if any servo's EEPROM changed since the last save.
  void save_state_if_changed();
  /// Keeps the physics world within 10 ms of simulated time, so that a read after a
  /// long quiet spell does not run all the ticks since at once.
  void schedule_physics_catch_up();

  RunOptions options_;
  boost::asio::io_context io_;
  sim::Scheduler scheduler_;
  io::RealTimeDriver driver_;
  faults::Injector injector_;     // outlives the buses (declared before ports_)
  sim::SimDuration handover_{0};  // subtracted from the arrival time of the client's bytes
  io::CpuWait cpu_wait_;          // marked when each handler ends
  // The world the servos drive (null without "physics"); outlives the servos coupled to it.
  std::unique_ptr<physics::WorldClock> world_;
  std::optional<control::PhysicsView> physics_view_;  // of world_, for the control API
  std::vector<std::unique_ptr<Port>> ports_;
  std::ofstream trace_;
  std::ofstream pcap_file_;
  std::unique_ptr<PcapWriter> pcap_;  // writes to pcap_file_; null without --pcap
  std::vector<std::vector<std::uint8_t>> saved_eeprom_;  // per servo, ports in order
  /// The servos' ControlTable::eeprom_changes() summed when saved_eeprom_ was last compared with
  /// them (each count only grows, so an equal sum means no EEPROM byte changed since).
  std::optional<std::uint64_t> checked_eeprom_changes_;
  /// A control connection that asked for trace events (trace.subscribe) and its ports (all when
  /// empty). The server reports every close, so the session pointer never dangles.
  struct Subscriber {
    io::ControlSession* session = nullptr;
    std::vector<std::string> ports;
  };
  std::map<std::uint64_t, Subscriber> subscribers_;  // by connection id
  io::ControlSession* current_session_ = nullptr;    // whose request is being handled
  std::unique_ptr<control::Api> api_;
  std::unique_ptr<io::ControlServer> control_;
  bool shutting_down_ = false;
};

}  // namespace dxlemu::app
