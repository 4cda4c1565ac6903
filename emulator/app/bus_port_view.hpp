#pragma once

#include <vector>

#include "bus/bus.hpp"
#include "control/port_view.hpp"

namespace dxlemu::app {

/// The control API's view of one bus: every call is the bus's own (docs/bus.md), so that the
/// daemon and the control API's tests wire a port the same way.
class BusPortView final : public control::PortView {
 public:
  /// A view of `bus`, which must outlive it.
  explicit BusPortView(bus::Bus& bus) : bus_(bus) {}

  std::vector<model::Servo*> servos() const override;
  void catch_up() override { bus_.catch_up(); }
  bool attached(const model::Servo& servo) const override { return bus_.attached(servo); }
  bool booting(const model::Servo& servo) const override { return bus_.booting(servo); }
  void detach(model::Servo& servo) override { bus_.detach(servo); }
  void power_on(model::Servo& servo) override { bus_.power_on(servo); }
  bus::BusStats stats() const override { return bus_.stats(); }

 private:
  bus::Bus& bus_;
};

}  // namespace dxlemu::app
