#include "app/config/make_servo.hpp"

namespace dxlemu::app {

std::unique_ptr<model::Servo> make_servo(const ModelLibrary& library, const ServoConfig& servo,
                                         sim::SimDuration tick) {
  auto made = std::make_unique<model::Servo>(library.find(servo.model), servo.id, tick);
  for (const auto& [key, value] : servo.items) {
    const std::size_t item = made->table().index(key);
    if (made->spec().items[item].area == model::Area::Eeprom) {
      made->table().restore_kept(item, value);
    } else {
      made->table().set(item, value);
    }
  }
  return made;
}

}  // namespace dxlemu::app
