#pragma once

#include <memory>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "model/servo.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::app {

/// The servo `servo` of a bus config asks for: its model from `library` at its ID, with a motion
/// tick of `tick`, and its item overrides applied as written before the emulator started. An
/// EEPROM override is kept over power cycles (as a state file's value is), so that it holds even
/// where a FEETECH Lock flag of 1 would lose a bus write; a RAM override is set as the servo's
/// value now. `servo` must have passed check_servo() against `library`.
std::unique_ptr<model::Servo> make_servo(const ModelLibrary& library, const ServoConfig& servo,
                                         sim::SimDuration tick);

}  // namespace dxlemu::app
