#pragma once

// The bus's private per-servo and per-reply records, shared by the files that implement Bus.

#include <optional>

#include "bus/bus.hpp"

namespace dxlemu::bus {

/// A servo and its bus-side state: whether it is on the line and awake, and its Bus Watchdog.
struct Bus::Node {
  model::Servo* servo = nullptr;
  std::size_t index = 0;         // its place in servos(), which the fault hooks name it by
  sim::SimTime booting_until{};  // silent before this (Reboot, Factory Reset, Backup restore)
  bool attached = true;          // plugged in: powered and on the line
  std::optional<sim::Scheduler::EventId> watchdog;  // the Bus Watchdog's expiry, while armed
};

/// A reply scheduled for delivery. A collision marks it cancelled: the event still runs (the
/// servo still applies deferred effects), but the bytes are not delivered.
struct Bus::Outgoing {
  bool cancelled = false;
};

}  // namespace dxlemu::bus
