#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "bus/bus.hpp"
#include "bus/loopback_link.hpp"
#include "control/target.hpp"
#include "faults/injector.hpp"
#include "shipped_model.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::fuzz {

/// A control::Target of ports of real servos on a hand-stepped clock (as tests/unit/control's),
/// for fuzz_control. The one difference from the daemon: clock.step runs at most kStepCap of
/// simulated time per request, because a long step of a moving servo costs a motion tick per
/// millisecond and would make the fuzzer report slow inputs instead of bugs.
class ControlTarget : public control::Target {
 public:
  /// Simulated time one step_clock() runs at most.
  static constexpr sim::SimDuration kStepCap = std::chrono::seconds(2);

  /// One port: its bus, and a link that records what the bus sends.
  struct Port {
    std::string name;
    bus::LoopbackLink link;
    bus::Bus bus;
    Port(std::string port_name, sim::Scheduler& scheduler)
        : name(std::move(port_name)), bus(scheduler, link) {}
  };

  /// Adds a port named `name` under the target's fault rules.
  Port& add_port(const std::string& name) {
    Port& port = ports_.emplace_back(name, scheduler_);
    port.bus.set_faults(&injector_, name);
    return port;
  }
  /// Adds a servo of the shipped model `model` with `id` to `port`.
  model::Servo& add(Port& port, const std::string& model, std::uint8_t id) {
    return port.bus.add_servo(std::make_unique<model::Servo>(test::shipped_model(model), id));
  }

  std::vector<std::string> port_names() const override {
    std::vector<std::string> names;
    for (const auto& port : ports_) {
      names.push_back(port.name);
    }
    return names;
  }
  bus::Bus* bus(std::string_view name) override {
    const auto it =
        std::find_if(ports_.begin(), ports_.end(), [&](const Port& p) { return p.name == name; });
    return it == ports_.end() ? nullptr : &it->bus;
  }
  nlohmann::json port_info(std::string_view name) const override {
    return {{"pty", "/dev/pts/" + std::string(name)}};
  }
  sim::SimTime now() const override { return scheduler_.now(); }
  bool manual_clock() const override { return true; }
  void step_clock(sim::SimDuration d) override { scheduler_.advance_by(std::min(d, kStepCap)); }
  faults::Injector& faults() override { return injector_; }
  void subscribe_trace(std::uint64_t /*client*/, std::vector<std::string> /*ports*/) override {}
  void unsubscribe_trace(std::uint64_t /*client*/) override {}
  void schedule_in(sim::SimDuration delay, std::function<void()> action) override {
    scheduler_.schedule_after(delay, std::move(action));
  }
  void warn(const std::string& /*message*/) override {}
  void request_shutdown() override {}

 private:
  sim::Scheduler scheduler_;
  faults::Injector injector_{1};
  std::deque<Port> ports_;  // a deque: buses stay where they were made
};

}  // namespace dxlemu::fuzz
