#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bus/bus_stats.hpp"
#include "bus/late_reply_guard.hpp"
#include "model/servo.hpp"

namespace dxlemu::control {

/// One port as the control commands see it: its servos, the bus-side state of each (plugged in,
/// booting) and what a hand on the cable does to it, and the port's counters. The commands read
/// and change a servo itself through model::Servo; everything about the line goes through here.
/// Target::port() hands it out; app::BusPortView implements it on a bus::Bus.
/// A servo of a port by the name the robot's software gives its joint (docs/robots.md "Joints"),
/// and the range the joint moves through, degrees of the shaft from its middle.
struct JointView {
  std::string name;
  std::uint8_t id = 0;
  std::optional<std::pair<double, double>> range_deg;
};

class PortView {
 public:
  virtual ~PortView() = default;

  /// The port's named joints, as its config names them; empty when it names none.
  virtual std::vector<JointView> joints() const { return {}; }

  /// The servos on the port, in the order the port was configured. The port owns them.
  virtual std::vector<model::Servo*> servos() const = 0;
  /// Brings every servo's motion up to the scheduler's time (before reading or changing a
  /// servo from outside the bus).
  virtual void catch_up() = 0;

  /// False while `servo` is unplugged (servo.detach).
  virtual bool attached(const model::Servo& servo) const = 0;
  /// True while `servo` is booting after a reboot or power-on (silent on the line).
  virtual bool booting(const model::Servo& servo) const = 0;
  /// Unplugs `servo`: it hears and answers nothing and gives no torque until power_on().
  virtual void detach(model::Servo& servo) = 0;
  /// Plugs `servo` in, or power-cycles it if it is plugged in; it then boots.
  virtual void power_on(model::Servo& servo) = 0;
  /// Executes `packet` on `servo` as if the bus had addressed it (a Reboot, a Factory Reset),
  /// with its effects applied now and nothing sent on the line; returns the servo's answer.
  virtual model::ServoResponse instruct(model::Servo& servo,
                                        const wire::InstructionPacket& packet) = 0;

  /// The port's counters since it was made.
  virtual bus::BusStats stats() const = 0;
  /// How late the port's replies went out against their modelled times (docs/timing.md "Late
  /// replies"); empty where nothing measures it (manual timing, tests).
  virtual std::optional<bus::LatenessSummary> lateness() const { return std::nullopt; }
};

}  // namespace dxlemu::control
