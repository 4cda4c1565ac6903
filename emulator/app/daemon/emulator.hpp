#pragma once

#include <boost/asio/io_context.hpp>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/daemon/run_options.hpp"
#include "app/daemon/state_keeper.hpp"
#include "app/daemon/trace_fan_out.hpp"
#include "control/api.hpp"
#include "control/target.hpp"
#include "io/control_server.hpp"
#include "io/cpu_wait.hpp"
#include "io/realtime_driver.hpp"
#include "io/web_server.hpp"
#include "physics/world_clock.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::app {

/// The running emulator: one io_context, one thread, a scheduler bound to the wall clock, a PTY,
/// its link chain (PortLinkChain) and a Bus per port, the state file (StateKeeper), the trace,
/// capture and trace subscribers (TraceFanOut), and the control socket. A facade: it wires these
/// parts together and runs them; construction opens everything or throws, so nothing runs
/// half-configured. It is the control API's Target (docs/control-api.md).
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
  std::shared_ptr<const model::Trajectory> trajectory(const std::string& file) override;
  sim::SimTime now() const override;
  bool manual_clock() const override;
  std::string_view timing() const override;
  void step_clock(sim::SimDuration d) override;
  void request_shutdown() override;
  faults::Injector& faults() override { return injector_; }
  void subscribe_trace(const control::Connection& connection,
                       std::vector<std::string> ports) override;
  void unsubscribe_trace(std::uint64_t connection) override;
  void schedule_in(sim::SimDuration delay, std::function<void()> action) override;
  void warn(const std::string& message) override;

  /// Writes one readiness line per port (JSON) to `out`, serves until SIGINT or SIGTERM, then
  /// saves the state and returns; the destructor removes the links.
  void run(std::ostream& out);

 private:
  struct Port;
  /// What every I/O handler does last: flushes the trace file and saves the state if it changed.
  void finish_handler();
  /// Answers one request line of either transport (the control socket, the web interface),
  /// with the bus brought up to now first and its replies sent after.
  std::string handle_request(std::string_view line, const control::Connection& connection);
  /// Serves the web interface at options_.web (docs/web.md) and logs its URL.
  void start_web();
  /// Puts on each port the hands its config starts with (--hand, "hand"). Throws
  /// std::invalid_argument naming where the hand was given and why it is refused.
  void start_hands();
  /// Keeps the physics world, and the servos a hand moves, within 10 ms of simulated time, so
  /// that a read after a long quiet spell does not run all the ticks since at once: while
  /// there is such motion, an event every 10 ms catches them up. Called whenever a hand may
  /// have been put on a servo.
  void keep_motion_caught_up();
  /// There is a world or a hand on some servo.
  bool motion_to_catch_up() const;

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
  std::unique_ptr<StateKeeper> state_;
  std::unique_ptr<TraceFanOut> trace_;  // every bus's observer: outlives the buses
  std::vector<std::unique_ptr<Port>> ports_;
  std::unique_ptr<control::Api> api_;
  std::unique_ptr<io::ControlServer> control_;
  std::unique_ptr<io::WebServer> web_;  // with --web
  bool shutting_down_ = false;
  bool catching_up_ = false;  // keep_motion_caught_up()'s event is scheduled
};

}  // namespace dxlemu::app
