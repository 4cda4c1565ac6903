#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "control/connection.hpp"
#include "control/physics_view.hpp"
#include "control/port_view.hpp"
#include "control/scenario_registry.hpp"
#include "faults/injector.hpp"
#include "model/hand/trajectory.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::control {

/// What the control API sees and does: the facade every command goes through, so that control/
/// never reaches into the daemon's wiring. app::Emulator implements it; unit tests use a double.
/// Single-threaded: called from the one thread that runs the buses.
class Target {
 public:
  virtual ~Target() = default;
  /// The port names, in config order.
  virtual std::vector<std::string> port_names() const = 0;
  /// The port named `name`, or nullptr when there is no such port. The target owns it.
  virtual PortView* port(std::string_view name) = 0;
  /// Extra facts about a port for `list` (e.g. {"pty": "...", "link": "..."}): an object, which
  /// may be empty (or null).
  virtual nlohmann::json port_info(std::string_view port) const = 0;
  /// The physics world the servos drive, or nullptr when the config has none. The target owns it.
  virtual PhysicsView* physics() = 0;
  /// The trajectory a hand plays (docs/hands.md): the file `file`, or the shipped trajectory of
  /// that name. Throws std::exception whose what() names the file, the line and the reason when
  /// it cannot be read or is not a valid trajectory.
  virtual std::shared_ptr<const model::Trajectory> trajectory(const std::string& file) = 0;
  /// Simulated time now (the scheduler's clock).
  virtual sim::SimTime now() const = 0;
  /// True when simulated time only moves by clock.step (--timing manual).
  virtual bool manual_clock() const = 0;
  /// How simulated time runs (`--timing`): "realtime", "fast" or "manual" (clock.now says it).
  virtual std::string_view timing() const = 0;
  /// Moves simulated time forward by `d`, running everything due (manual timing only).
  virtual void step_clock(sim::SimDuration d) = 0;
  /// The fault rules every bus applies (docs/faults.md). The target owns them; every bus follows
  /// a change of them at once.
  virtual faults::Injector& faults() = 0;
  /// Sends every packet of `ports` (all ports when empty) to `connection` as trace events from
  /// now on, replacing an earlier subscription of that connection (trace.subscribe). The target
  /// keeps a copy of `connection` until it unsubscribes or the connection closes.
  virtual void subscribe_trace(const Connection& connection, std::vector<std::string> ports) = 0;
  /// Ends the trace events of connection `connection` (its id); nothing happens if it has none.
  virtual void unsubscribe_trace(std::uint64_t connection) = 0;
  /// Runs `action` once simulated time has advanced by `delay` (scenario steps).
  virtual void schedule_in(sim::SimDuration delay, std::function<void()> action) = 0;
  /// Reports a problem that has no request to answer (a scenario step that failed).
  virtual void warn(const std::string& message) = 0;
  /// Asks the daemon to stop after this reply.
  virtual void request_shutdown() = 0;

  /// The scenarios loaded so far and how far each has run (scenario.list). The control API's own
  /// bookkeeping, kept here because the scheduled steps and the commands both reach the target:
  /// implementations have nothing to do for it.
  ScenarioRegistry& scenarios() { return scenarios_; }
  const ScenarioRegistry& scenarios() const { return scenarios_; }

 private:
  ScenarioRegistry scenarios_;
};

}  // namespace dxlemu::control
