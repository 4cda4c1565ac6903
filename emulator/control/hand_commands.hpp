#pragma once

#include "control/request.hpp"
#include "control/target.hpp"

// The control API's commands on virtual hands: hand, hand.play, hand.sweep, hand.move and
// hand.stop (docs/control-api.md, docs/hands.md). Each puts a model::TrajectoryHand on the
// servos it names; the others keep theirs.
namespace dxlemu::control {

/// hand {"port"?}: every servo a hand holds, on the port or on every port: its joint, what the
/// hand plays, where it holds the shaft now and whether it has ended.
ordered_json hand_state(Target& target, const Args& args);

/// hand.play {"port"?, "file", "loop"?, "speed"?, "start_s"?, "interpolation"?,
/// "force_limit_nm"?}: plays the trajectory file (or shipped trajectory) on the joints its
/// columns name, from now on. Refused, changing nothing, for a file that is not a valid
/// trajectory, a column that names no joint or servo of the port, or a value outside a joint's
/// range, naming the file, the line and the reason.
ordered_json hand_play(Target& target, const Args& args);

/// hand.sweep {"port"?, "joints"?, "order"?, "speed_deg_s"?, "to"?, "force_limit_nm"?}: moves
/// the joints (all of the port's when not given) to the middle of their range, then through the
/// whole range and back, one after another or together, as LeRobot's calibration asks a
/// person to; with "to": "middle", only to the middle.
ordered_json hand_sweep(Target& target, const Args& args);

/// hand.move {"port"?, "joint", "position", "units"?, "duration_s"?, "force_limit_nm"?}: moves
/// one joint from where it is to `position` over `duration_s`, easing in and out.
ordered_json hand_move(Target& target, const Args& args);

/// hand.stop {"port"?, "joints"?}: the hand lets go of the joints (all of the port's when not
/// given); a torque-off shaft stays where it was left.
ordered_json hand_stop(Target& target, const Args& args);

/// Refuses a hand request that would be refused when run, without running it (Api::check, for
/// scenario steps): the file is read and checked against the port's joints.
void check_hand_request(Target& target, const Args& args);

}  // namespace dxlemu::control
