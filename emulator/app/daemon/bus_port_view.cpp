#include "app/daemon/bus_port_view.hpp"

namespace dxlemu::app {

std::vector<model::Servo*> BusPortView::servos() const {
  std::vector<model::Servo*> out;
  out.reserve(bus_.servos().size());
  for (const auto& servo : bus_.servos()) {
    out.push_back(servo.get());
  }
  return out;
}

std::optional<bus::LatenessSummary> BusPortView::lateness() const {
  if (guard_ == nullptr) {
    return std::nullopt;
  }
  return guard_->summary();
}

}  // namespace dxlemu::app
