#pragma once

#include "control/request.hpp"

// The control API's commands on ports and on the bus side of a servo: list, stats and the
// cable's servo.detach, servo.attach and servo.power_cycle, and
// the Reboot and Factory Reset a tool sends (docs/control-api.md).
namespace dxlemu::control {

/// list: every port with its facts and the key state of each servo.
ordered_json list(Target& target, const Args& args);
/// stats {"port"}: the counters of one port, or of every port.
ordered_json stats(Target& target, const Args& args);
/// servo.detach {"port", "servo"}: unplugs a servo; refused if it is unplugged already.
ordered_json servo_detach(Target& target, const Args& args);
/// servo.attach {"port", "servo"}: plugs an unplugged servo in; it boots.
ordered_json servo_attach(Target& target, const Args& args);
/// servo.power_cycle {"port", "servo"}: powers a servo on, or off and on again; it boots.
ordered_json servo_power_cycle(Target& target, const Args& args);
/// servo.reboot {"port", "servo"}: the Reboot instruction, as if sent on the bus (no status).
ordered_json servo_reboot(Target& target, const Args& args);
/// servo.factory_reset {"port", "servo", "keep"}: the Factory Reset instruction, keeping
/// "none" (default), the "id", or the "id_baud".
ordered_json servo_factory_reset(Target& target, const Args& args);

}  // namespace dxlemu::control
