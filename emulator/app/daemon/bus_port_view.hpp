#pragma once

#include <utility>
#include <vector>

#include "bus/bus.hpp"
#include "control/port_view.hpp"

namespace dxlemu::app {

/// The control API's view of one bus: every call is the bus's own (docs/bus.md), so that the
/// daemon and the control API's tests wire a port the same way.
class BusPortView final : public control::PortView {
 public:
  /// A view of `bus`, and of the guard that measures how late its replies go out if there is
  /// one; both must outlive the view.
  explicit BusPortView(bus::Bus& bus, const bus::LateReplyGuard* guard = nullptr)
      : bus_(bus), guard_(guard) {}

  /// Names the port's joints (the config's "joints") for joints().
  void set_joints(std::vector<control::JointView> joints) { joints_ = std::move(joints); }
  std::vector<control::JointView> joints() const override { return joints_; }
  std::vector<model::Servo*> servos() const override;
  void catch_up() override { bus_.catch_up(); }
  bool attached(const model::Servo& servo) const override { return bus_.attached(servo); }
  bool booting(const model::Servo& servo) const override { return bus_.booting(servo); }
  void detach(model::Servo& servo) override { bus_.detach(servo); }
  void power_on(model::Servo& servo) override { bus_.power_on(servo); }
  model::ServoResponse instruct(model::Servo& servo,
                                const wire::InstructionPacket& packet) override {
    return bus_.instruct(servo, packet);
  }
  bus::BusStats stats() const override { return bus_.stats(); }
  std::optional<bus::LatenessSummary> lateness() const override;

 private:
  bus::Bus& bus_;
  const bus::LateReplyGuard* guard_;
  std::vector<control::JointView> joints_;
};

}  // namespace dxlemu::app
