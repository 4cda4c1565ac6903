#include "model/motion/present_values.hpp"

namespace dxlemu::model {

void PresentValues::publish() {
  const MotionItems& items = motion_.items;
  motion_.put(items.present_voltage,
              round_to(motion_.conditions.supply_v * items.voltage_counts_per_v));
  motion_.put(items.present_temperature, round_to(motion_.motor.state().temperature_c));
  position_ = motion_.get(items.present_position);
  temperature_ = motion_.get(items.present_temperature);
  voltage_ = motion_.get(items.present_voltage);
}

bool PresentValues::absorb(const Drive& drive) {
  const MotionItems& items = motion_.items;
  const ControlTable& table = motion_.table;
  bool moved = false;
  if (items.present_position && table.get(*items.present_position) != position_) {
    position_ = table.get(*items.present_position);
    // A single-turn reading names an angle, not a turn: the shaft moves the least way to it, so
    // a reading set step by step across 4095 and 0 turns it on, not back a whole turn.
    motion_.motor.set_position(
        drive.raw_goal(motion_.unwrapped(position_, MotionContext::Turn::Nearest)));
    moved = true;
  }
  if (items.present_temperature && table.get(*items.present_temperature) != temperature_) {
    temperature_ = table.get(*items.present_temperature);
    motion_.motor.set_temperature(static_cast<double>(temperature_));
    moved = true;
  }
  if (items.present_voltage && table.get(*items.present_voltage) != voltage_) {
    voltage_ = table.get(*items.present_voltage);
    motion_.conditions.supply_v = static_cast<double>(voltage_) / items.voltage_counts_per_v;
    moved = true;
  }
  return moved;
}

}  // namespace dxlemu::model
