#include "control/hand_commands.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "model/hand/joint_scale.hpp"
#include "model/hand/playback.hpp"
#include "model/hand/sweep.hpp"
#include "model/hand/trajectory_hand.hpp"
#include "model/motion/motion_items.hpp"

namespace dxlemu::control {
namespace {

using model::JointUnit;

// hand.sweep's speed when not given: a steady sweep a person makes, a whole SO-101 joint in
// about 2.5 s.
constexpr double kDefaultSweepDegS = 90;
constexpr double kMaxSweepDegS = 3600;
// hand.move's duration when not given, and its bounds (a tick; an hour).
constexpr double kDefaultMoveS = 1;
constexpr double kMinMoveS = 0.001;
constexpr double kMaxMoveS = 3600;
// A move eases in and out along half a cosine, given as this many keyframes to the cubic.
constexpr int kMoveKeyframes = 17;
// Bounds of a hand's force (N·m, as condition.set's external_load) and of a playback speed.
constexpr double kMaxForceNm = 1000;
constexpr double kMaxPlaySpeed = 1000;
// How far outside a range a value may be and still count as in it: rounding in the file's
// decimals, not a real excess.
constexpr double kRangeSlack = 1e-6;

/// A joint a hand can hold: a servo of the port, its name, and the range it moves through.
struct HandJoint {
  model::Servo* servo = nullptr;
  /// The joint's name, or the servo's ID in decimal when the port names no joint for it.
  std::string name;
  std::optional<std::pair<double, double>> range_deg;
  model::JointScale scale;
};

/// Where a joint may be: its range in degrees, or the servo's factory position limits in raw.
struct Span {
  double low = 0;
  double high = 0;
  JointUnit unit = JointUnit::Degrees;
};

/// Hands to put on servos, all checked: nothing is applied until every one is.
struct Placement {
  model::Servo* servo = nullptr;
  std::shared_ptr<const model::Hand> hand;
};

std::string number_text(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.6g", value);
  return buffer.data();
}

std::string unit_text(JointUnit unit) {
  return unit == JointUnit::Degrees ? "°" : " raw";
}

HandJoint make_joint(model::Servo& servo, const std::vector<JointView>& named) {
  HandJoint joint{&servo, std::to_string(servo.id()), std::nullopt,
                  model::JointScale::of(servo.spec())};
  for (const JointView& view : named) {
    if (view.id == servo.id()) {
      joint.name = view.name;
      joint.range_deg = view.range_deg;
    }
  }
  return joint;
}

/// Every joint of the port: its named joints in the config's order; without names, every servo.
std::vector<HandJoint> joints_of(const Port& port) {
  const std::vector<JointView> named = port.view.joints();
  std::vector<HandJoint> joints;
  if (!named.empty()) {
    for (const JointView& view : named) {
      joints.push_back(make_joint(servo_on(port, view.id), named));
    }
    return joints;
  }
  for (model::Servo* servo : port.view.servos()) {
    joints.push_back(make_joint(*servo, named));
  }
  return joints;
}

std::optional<std::int64_t> decimal_id(std::string_view text) {
  std::int64_t id = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (error != std::errc() || end != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return id;
}

/// The joint `name` (a joint's name, or a servo's ID in decimal) of `port`; nullopt when the port
/// has none of that name.
std::optional<HandJoint> find_joint(const Port& port, const std::string& name) {
  const std::vector<JointView> named = port.view.joints();
  for (const JointView& view : named) {
    if (view.name == name) {
      return make_joint(servo_on(port, view.id), named);
    }
  }
  if (const auto id = decimal_id(name)) {
    for (model::Servo* servo : port.view.servos()) {
      if (servo->id() == *id) {
        return make_joint(servo_on(port, *id), named);
      }
    }
  }
  return std::nullopt;
}

std::string known_joints(const Port& port) {
  std::vector<std::string> names;
  for (const JointView& view : port.view.joints()) {
    names.push_back(view.name);
  }
  std::vector<std::string> ids;
  for (model::Servo* servo : port.view.servos()) {
    ids.push_back(std::to_string(servo->id()));
  }
  return (names.empty() ? "it names no joints" : "its joints: " + joined(names)) +
         "; or a servo ID: " + (ids.empty() ? "none" : joined(ids));
}

HandJoint joint_named(const Port& port, const std::string& name) {
  if (auto joint = find_joint(port, name)) {
    return *joint;
  }
  refuse("no joint " + json_quoted(name) + " on port " + port.name + " (" + known_joints(port) +
         ")");
}

std::optional<Span> span_of(const HandJoint& joint) {
  if (joint.range_deg) {
    return Span{joint.range_deg->first, joint.range_deg->second, JointUnit::Degrees};
  }
  const model::ModelSpec& spec = joint.servo->spec();
  const model::MotionItems items(spec);
  std::optional<std::size_t> low = items.min_position_limit;
  std::optional<std::size_t> high = items.max_position_limit;
  if (!low || !high) {
    low = items.cw_angle_limit;
    high = items.ccw_angle_limit;
  }
  if (!low || !high) {
    return std::nullopt;
  }
  return Span{static_cast<double>(spec.items[*low].initial),
              static_cast<double>(spec.items[*high].initial), JointUnit::Raw};
}

std::string span_text(const Span& span) {
  return (span.unit == JointUnit::Degrees ? "its range " : "the servo's position limits ") +
         number_text(span.low) + " ~ " + number_text(span.high) + unit_text(span.unit);
}

/// Refuses `value` (in `unit`) of `joint` outside its span; `where` prefixes the message.
void check_in_span(const HandJoint& joint, double value, JointUnit unit, const std::string& where) {
  const std::optional<Span> span = span_of(joint);
  if (!span) {
    return;
  }
  const double in_span = joint.scale.from_pulses(joint.scale.to_pulses(value, unit), span->unit);
  if (in_span < span->low - kRangeSlack || in_span > span->high + kRangeSlack) {
    refuse(where + joint.name + " " + number_text(value) + unit_text(unit) + " is outside " +
           span_text(*span));
  }
}

double bounded_number(const Args& args, std::string_view key, double fallback, double low,
                      double high, std::string_view unit) {
  const auto value = args.number(key);
  if (!value) {
    return fallback;
  }
  if (!(*value >= low && *value <= high)) {
    refuse(json_quoted(key) + " must be " + number_text(low) + " ~ " + number_text(high) +
           std::string(unit) + ", got " + args.text(key));
  }
  return *value;
}

double force_of(const Args& args) {
  const double force =
      bounded_number(args, "force_limit_nm", model::kDefaultHandForceNm, 0, kMaxForceNm, " N·m");
  if (force <= 0) {
    refuse("\"force_limit_nm\" must be more than 0 N·m");
  }
  return force;
}

JointUnit unit_of(const Args& args) {
  const auto units = args.string("units");
  if (!units || *units == "deg") {
    return JointUnit::Degrees;
  }
  if (*units == "raw") {
    return JointUnit::Raw;
  }
  refuse("\"units\" must be \"deg\" or \"raw\", got " + args.text("units"));
}

/// The joints "joints" names (an array of names or IDs), or every joint of the port.
std::vector<HandJoint> chosen_joints(const Port& port, const Args& args) {
  const ordered_json* list = args.value("joints");
  if (list == nullptr) {
    std::vector<HandJoint> all = joints_of(port);
    if (all.empty()) {
      refuse("port " + port.name + " has no servos");
    }
    return all;
  }
  if (!list->is_array() || list->empty()) {
    refuse("\"joints\" must be a non-empty array of joint names or servo IDs");
  }
  std::vector<HandJoint> joints;
  for (const auto& entry : *list) {
    std::string name;
    if (entry.is_string()) {
      name = entry.get<std::string>();
    } else if (entry.is_number_integer()) {
      name = std::to_string(entry.get<std::int64_t>());
    } else {
      refuse("\"joints\" must hold joint names or servo IDs, got " + dumped(entry));
    }
    HandJoint joint = joint_named(port, name);
    if (std::any_of(joints.begin(), joints.end(),
                    [&](const HandJoint& j) { return j.servo == joint.servo; })) {
      refuse("\"joints\" names " + joint.name + " twice");
    }
    joints.push_back(std::move(joint));
  }
  return joints;
}

/// Where the hand holds `joint` now (or, without a hand, where its shaft is), in `unit`.
double hand_value_now(Target& target, const HandJoint& joint, JointUnit unit) {
  const auto* hand = dynamic_cast<const model::TrajectoryHand*>(joint.servo->motion().hand());
  if (hand != nullptr) {
    if (const auto grip = hand->grip(target.now())) {
      return joint.scale.from_pulses(grip->position, unit);
    }
  }
  return joint.scale.from_pulses(joint.servo->motion().motor().position, unit);
}

void place_hands(const Port& port, const std::vector<Placement>& placements) {
  // Motion up to now runs without the new hands; they hold from now on.
  port.view.catch_up();
  for (const Placement& placement : placements) {
    placement.servo->motion().set_hand(placement.hand);
  }
}

ordered_json placed_json(const Port& port, const std::vector<HandJoint>& joints,
                         const model::Trajectory& trajectory, const model::Playback& playback) {
  ordered_json list = ordered_json::array();
  for (const HandJoint& joint : joints) {
    list.push_back({{"joint", joint.name}, {"servo", joint.servo->id()}});
  }
  return {{"port", port.name},
          {"origin", trajectory.origin()},
          {"duration_s", (trajectory.duration_s() - playback.start_s) / playback.speed},
          {"loop", playback.loop},
          {"joints", std::move(list)}};
}

std::shared_ptr<const model::Hand> hand_for(
    const std::shared_ptr<const model::Trajectory>& trajectory, std::size_t column,
    const model::Playback& playback, Target& target, const HandJoint& joint, double force,
    model::HandSource source) {
  return std::make_shared<model::TrajectoryHand>(trajectory, column, playback, target.now(),
                                                 joint.scale, force, source);
}

// --- hand.play ---------------------------------------------------------------------------------

model::Playback playback_of(const Args& args) {
  model::Playback playback;
  if (const auto interpolation = args.string("interpolation")) {
    if (*interpolation == "linear") {
      playback.interpolation = model::Interpolation::Linear;
    } else if (*interpolation != "cubic") {
      refuse("\"interpolation\" must be \"linear\" or \"cubic\", got " +
             args.text("interpolation"));
    }
  }
  playback.loop = args.boolean("loop").value_or(false);
  playback.speed = bounded_number(args, "speed", 1, 0, kMaxPlaySpeed, "");
  if (playback.speed <= 0) {
    refuse("\"speed\" must be more than 0");
  }
  playback.start_s = bounded_number(args, "start_s", 0, 0, model::Trajectory::kMaxTimeS, " s");
  return playback;
}

struct PreparedPlay {
  std::vector<Placement> placements;
  ordered_json result;
};

PreparedPlay prepare_play(Target& target, const Port& port, const Args& args) {
  const auto file = args.string("file");
  if (!file) {
    refuse("\"file\" is required: a trajectory file, or a shipped trajectory's name");
  }
  const model::Playback playback = playback_of(args);
  const double force = force_of(args);
  std::shared_ptr<const model::Trajectory> trajectory;
  try {
    trajectory = target.trajectory(*file);
  } catch (const std::exception& e) {
    refuse(e.what());
  }
  if (playback.start_s > trajectory->duration_s()) {
    refuse("\"start_s\" " + number_text(playback.start_s) + " s is after the end of " +
           trajectory->origin() + " (" + number_text(trajectory->duration_s()) + " s)");
  }
  const std::string header =
      trajectory->origin() + ": line " + std::to_string(trajectory->columns_line()) + ": ";
  std::vector<HandJoint> joints;
  PreparedPlay prepared;
  for (std::size_t c = 0; c < trajectory->columns().size(); ++c) {
    const model::TrajectoryColumn& column = trajectory->columns()[c];
    const std::optional<HandJoint> joint = find_joint(port, column.joint);
    if (!joint) {
      refuse(header + "no joint " + json_quoted(column.joint) + " on port " + port.name + " (" +
             known_joints(port) + ")");
    }
    for (const HandJoint& other : joints) {
      if (other.servo == joint->servo) {
        refuse(header + "columns " + json_quoted(other.name) + " and " + json_quoted(column.joint) +
               " are the same servo, " + std::to_string(joint->servo->id()));
      }
    }
    for (std::size_t r = 0; r < trajectory->row_count(); ++r) {
      check_in_span(*joint, trajectory->value(r, c), column.unit,
                    trajectory->origin() + ": line " + std::to_string(trajectory->line(r)) + ": ");
    }
    joints.push_back(*joint);
    prepared.placements.push_back({joint->servo, hand_for(trajectory, c, playback, target, *joint,
                                                          force, model::HandSource::File)});
  }
  prepared.result = placed_json(port, joints, *trajectory, playback);
  return prepared;
}

// --- hand.sweep --------------------------------------------------------------------------------

PreparedPlay prepare_sweep(Target& target, const Port& port, const Args& args) {
  const double speed_deg_s =
      bounded_number(args, "speed_deg_s", kDefaultSweepDegS, 0, kMaxSweepDegS, " °/s");
  if (speed_deg_s <= 0) {
    refuse("\"speed_deg_s\" must be more than 0 °/s");
  }
  model::SweepOrder order = model::SweepOrder::OneByOne;
  if (const auto given = args.string("order")) {
    if (*given == "together") {
      order = model::SweepOrder::Together;
    } else if (*given != "one_by_one") {
      refuse("\"order\" must be \"one_by_one\" or \"together\", got " + args.text("order"));
    }
  }
  // "to": "middle" stops at the middle: where LeRobot's calibration first asks for the arm.
  bool middle_only = false;
  if (const auto to = args.string("to")) {
    if (*to != "middle") {
      refuse("\"to\" must be \"middle\" (only to the middle of each range), got " +
             args.text("to"));
    }
    middle_only = true;
  }
  const double force = force_of(args);
  const std::vector<HandJoint> joints = chosen_joints(port, args);
  std::vector<model::SweepJoint> sweep;
  for (const HandJoint& joint : joints) {
    const std::optional<Span> span = span_of(joint);
    if (!span) {
      refuse(joint.name +
             " has no range to sweep: give the port's joints a range_deg "
             "(docs/robots.md \"Joints\")");
    }
    model::SweepJoint entry;
    entry.joint = joint.name;
    entry.unit = span->unit;
    entry.start = hand_value_now(target, joint, span->unit);
    entry.low = span->low;
    entry.high = span->high;
    entry.middle = (span->low + span->high) / 2;
    if (middle_only) {
      entry.low = entry.middle;
      entry.high = entry.middle;
    }
    entry.speed_per_s =
        speed_deg_s * joint.scale.pulses_per_degree / joint.scale.pulses_per(span->unit);
    sweep.push_back(std::move(entry));
  }
  model::Playback playback;
  playback.interpolation = model::Interpolation::Linear;
  const auto trajectory =
      std::make_shared<const model::Trajectory>(model::make_sweep(sweep, order));
  PreparedPlay prepared;
  for (std::size_t c = 0; c < joints.size(); ++c) {
    prepared.placements.push_back(
        {joints[c].servo,
         hand_for(trajectory, c, playback, target, joints[c], force, model::HandSource::Sweep)});
  }
  prepared.result = placed_json(port, joints, *trajectory, playback);
  return prepared;
}

// --- hand.move ---------------------------------------------------------------------------------

PreparedPlay prepare_move(Target& target, const Port& port, const Args& args) {
  std::string name;
  if (const ordered_json* given = args.value("joint");
      given != nullptr && given->is_number_integer()) {
    name = std::to_string(given->get<std::int64_t>());
  } else if (auto text = args.string("joint")) {
    name = std::move(*text);
  } else {
    refuse("\"joint\" is required: a joint's name or a servo ID");
  }
  const HandJoint joint = joint_named(port, name);
  const auto position = args.number("position");
  if (!position) {
    refuse("\"position\" is required");
  }
  const JointUnit unit = unit_of(args);
  check_in_span(joint, *position, unit, "");
  const double duration =
      bounded_number(args, "duration_s", kDefaultMoveS, kMinMoveS, kMaxMoveS, " s");
  const double force = force_of(args);
  // Half a cosine from here to there: a hand starts and stops gently.
  const double from = hand_value_now(target, joint, unit);
  std::vector<double> times;
  std::vector<std::vector<double>> rows;
  for (int k = 0; k < kMoveKeyframes; ++k) {
    const double share = static_cast<double>(k) / (kMoveKeyframes - 1);
    times.push_back(duration * share);
    rows.push_back({from + (*position - from) * (1 - std::cos(std::numbers::pi * share)) / 2});
  }
  const auto trajectory = std::make_shared<const model::Trajectory>(
      std::vector<model::TrajectoryColumn>{{joint.name, unit}}, times, rows,
      std::vector<std::size_t>{}, "move");
  const model::Playback playback;
  PreparedPlay prepared;
  prepared.placements.push_back({joint.servo, hand_for(trajectory, 0, playback, target, joint,
                                                       force, model::HandSource::Move)});
  prepared.result = placed_json(port, {joint}, *trajectory, playback);
  return prepared;
}

std::string source_name(model::HandSource source) {
  switch (source) {
    case model::HandSource::File:
      return "file";
    case model::HandSource::Sweep:
      return "sweep";
    case model::HandSource::Move:
      return "move";
  }
  return "file";
}

ordered_json port_hands(Target& target, const Port& port) {
  ordered_json list = ordered_json::array();
  const std::vector<JointView> named = port.view.joints();
  for (model::Servo* servo : port.view.servos()) {
    const auto* hand = dynamic_cast<const model::TrajectoryHand*>(servo->motion().hand());
    if (hand == nullptr) {
      continue;
    }
    const HandJoint joint = make_joint(*servo, named);
    const JointUnit unit = hand->trajectory().columns()[hand->column()].unit;
    list.push_back({{"port", port.name},
                    {"servo", servo->id()},
                    {"joint", joint.name},
                    {"source", source_name(hand->source())},
                    {"origin", hand->trajectory().origin()},
                    {"value", hand->value_at(target.now())},
                    {"units", unit == JointUnit::Degrees ? "deg" : "raw"},
                    {"loop", hand->playback().loop},
                    {"ended", hand->ended(target.now())},
                    {"force_limit_nm", hand->force_limit_nm()}});
  }
  return list;
}

using Prepare = PreparedPlay (*)(Target& target, const Port& port, const Args& args);

// Checks the whole request, then puts its hands on the servos from now on.
ordered_json run_prepared(Target& target, const Args& args, Prepare prepare) {
  const Port port = port_of(target, args);
  port.view.catch_up();
  PreparedPlay prepared = prepare(target, port, args);
  place_hands(port, prepared.placements);
  return std::move(prepared.result);
}

}  // namespace

ordered_json hand_state(Target& target, const Args& args) {
  if (args.has("port")) {
    return port_hands(target, port_of(target, args));
  }
  ordered_json all = ordered_json::array();
  for (const std::string& name : target.port_names()) {
    if (PortView* view = target.port(name)) {
      for (auto& entry : port_hands(target, Port{name, *view})) {
        all.push_back(std::move(entry));
      }
    }
  }
  return all;
}

ordered_json hand_play(Target& target, const Args& args) {
  return run_prepared(target, args, prepare_play);
}

ordered_json hand_sweep(Target& target, const Args& args) {
  return run_prepared(target, args, prepare_sweep);
}

ordered_json hand_move(Target& target, const Args& args) {
  return run_prepared(target, args, prepare_move);
}

ordered_json hand_stop(Target& target, const Args& args) {
  const Port port = port_of(target, args);
  const std::vector<HandJoint> joints = chosen_joints(port, args);
  port.view.catch_up();
  ordered_json released = ordered_json::array();
  for (const HandJoint& joint : joints) {
    if (joint.servo->motion().hand() != nullptr) {
      joint.servo->motion().set_hand(nullptr);
      released.push_back({{"joint", joint.name}, {"servo", joint.servo->id()}});
    }
  }
  return {{"port", port.name}, {"released", std::move(released)}};
}

void check_hand_request(Target& target, const Args& args) {
  const Port port = port_of(target, args);
  const std::string_view command = args.command();
  if (command == "hand.play") {
    prepare_play(target, port, args);
  } else if (command == "hand.sweep") {
    prepare_sweep(target, port, args);
  } else if (command == "hand.move") {
    prepare_move(target, port, args);
  } else if (command == "hand.stop") {
    chosen_joints(port, args);
  }
}

}  // namespace dxlemu::control
