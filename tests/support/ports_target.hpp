#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/daemon/bus_port_view.hpp"
#include "bus/bus.hpp"
#include "bus/loopback_link.hpp"
#include "control/target.hpp"
#include "faults/injector.hpp"
#include "faults/port_faults.hpp"
#include "model/hand/trajectory.hpp"
#include "shipped_model.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::test {

/// A control::Target of ports of real servos on a hand-stepped clock, for the control API's unit
/// tests and its fuzz target (header-only: users link dxlemu_app). What the daemon would do
/// outside the API (trace subscriptions, warnings, shutdown) is recorded for the tests to check.
class PortsTarget : public control::Target {
 public:
  /// One port: its bus, a link that records what the bus sends, the fault rules as the bus meets
  /// them, and the bus as the control API sees it (the daemon's own view).
  struct Port {
    std::string name;
    bus::LoopbackLink link;
    bus::Bus bus;
    faults::PortFaults faults;
    app::BusPortView view{bus};
    Port(std::string port_name, sim::Scheduler& scheduler)
        : name(std::move(port_name)), bus(scheduler, link), faults(scheduler, bus.servos()) {}
  };

  sim::Scheduler scheduler;
  faults::Injector injector{1};
  std::deque<Port> ports;  // a deque: buses stay where they were made
  bool manual = true;      // what manual_clock() says
  bool shutdown_requested = false;
  std::map<std::uint64_t, std::vector<std::string>> subscriptions;  // by client
  std::vector<std::string> warnings;
  control::PhysicsView* world = nullptr;  // what physics() returns
  /// What trajectory() returns for a name; any other is refused (no file is read: the control
  /// API's fuzz target runs on this target).
  std::map<std::string, std::shared_ptr<const model::Trajectory>> trajectories;

  /// Adds a port named `name` under the target's fault rules.
  Port& add_port(const std::string& name) {
    Port& port = ports.emplace_back(name, scheduler);
    port.faults.set_rules(&injector, name);
    port.bus.set_faults(&port.faults);
    return port;
  }
  /// Adds a servo of the shipped model `model` with `id` to `port`.
  model::Servo& add(Port& port, const std::string& model, std::uint8_t id) {
    return port.bus.add_servo(std::make_unique<model::Servo>(shipped_model(model), id));
  }

  std::vector<std::string> port_names() const override {
    std::vector<std::string> names;
    for (const auto& port : ports) {
      names.push_back(port.name);
    }
    return names;
  }
  control::PortView* port(std::string_view name) override {
    for (auto& port : ports) {
      if (port.name == name) {
        return &port.view;
      }
    }
    return nullptr;
  }
  nlohmann::json port_info(std::string_view name) const override {
    return {{"pty", "/dev/pts/" + std::string(name)}};
  }
  control::PhysicsView* physics() override { return world; }
  std::shared_ptr<const model::Trajectory> trajectory(const std::string& file) override {
    if (const auto known = trajectories.find(file); known != trajectories.end()) {
      return known->second;
    }
    throw std::invalid_argument(file + " is no trajectory of this test");
  }
  sim::SimTime now() const override { return scheduler.now(); }
  bool manual_clock() const override { return manual; }
  std::string_view timing() const override { return manual ? "manual" : "realtime"; }
  void step_clock(sim::SimDuration d) override { scheduler.advance_by(d); }
  void request_shutdown() override { shutdown_requested = true; }
  faults::Injector& faults() override { return injector; }
  void subscribe_trace(const control::Connection& connection,
                       std::vector<std::string> names) override {
    subscriptions[connection.id] = std::move(names);
  }
  void unsubscribe_trace(std::uint64_t client) override { subscriptions.erase(client); }
  void schedule_in(sim::SimDuration delay, std::function<void()> action) override {
    scheduler.schedule_at(scheduler.now() + delay, std::move(action));
  }
  void warn(const std::string& message) override { warnings.push_back(message); }
};

}  // namespace dxlemu::test
