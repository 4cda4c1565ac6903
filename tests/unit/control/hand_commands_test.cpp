// The control API's hand commands (control/hand_commands.hpp, docs/hands.md): play, sweep, move,
// stop and state on a port of six STS3215 named as LeRobot names an SO-101's motors, on a
// hand-stepped clock.
#include <catch2/catch.hpp>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "api_requests.hpp"
#include "app/config/trajectory_file.hpp"
#include "control/api.hpp"
#include "ports_target.hpp"

namespace dxlemu::test::hand_commands {

using nlohmann::json;

/// arm: an SO-101's six STS3215, IDs 1-6, named and ranged as robots/so101-leader.json names
/// them; torque off, as a leader arm is.
struct ArmRig : test::ApiRequests<ArmRig> {
  PortsTarget target;
  PortsTarget::Port& arm = target.add_port("arm");
  control::Api api{target};

  ArmRig() {
    const std::vector<std::string> names = {"shoulder_pan", "shoulder_lift", "elbow_flex",
                                            "wrist_flex",   "wrist_roll",    "gripper"};
    std::vector<control::JointView> joints;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto id = static_cast<std::uint8_t>(i + 1);
      target.add(arm, "feetech/sts3215", id);
      joints.push_back({names[i], id, std::pair{-100.0, 100.0}});
    }
    joints.back().range_deg = std::pair{-10.0, 100.0};
    arm.view.set_joints(joints);
  }
  void add_trajectory(const std::string& name, const std::string& text) {
    target.trajectories[name] = std::make_shared<const model::Trajectory>(
        app::parse_trajectory(text, name, app::TrajectoryFormat::Csv));
  }
  void step_ms(int ms) { result(R"({"cmd":"clock.step","ms":)" + std::to_string(ms) + "}"); }
  /// Present Position of servo `id`.
  std::int64_t present(int id) {
    return result(R"({"cmd":"get","servo":)" + std::to_string(id) +
                  R"(,"item":"present_position"})")["value"]
        .get<std::int64_t>();
  }
};

// 4096 pulses per turn: 2048 is 0°, 11.3777... pulses per degree.
constexpr double kPulsesPerDegree = 4096.0 / 360;

std::int64_t raw_of(double degrees) {
  return std::llround(2048 + degrees * kPulsesPerDegree);
}

}  // namespace dxlemu::test::hand_commands

using dxlemu::test::hand_commands::ArmRig;
using dxlemu::test::hand_commands::raw_of;

TEST_CASE("hand.play moves the joints its columns name, by name or by ID, in degrees or raw",
          "[control][hand]") {
  ArmRig rig;
  rig.add_trajectory("wave.csv",
                     "time,shoulder_pan,3:raw\n"
                     "0,0,2048\n"
                     "1,90,3048\n");
  const auto played =
      rig.result(R"({"cmd":"hand.play","file":"wave.csv","interpolation":"linear"})");
  CHECK(played["joints"] ==
        nlohmann::json::parse(
            R"([{"joint":"shoulder_pan","servo":1},{"joint":"elbow_flex","servo":3}])"));
  CHECK(played["duration_s"] == 1.0);
  rig.step_ms(500);
  CHECK(rig.present(1) == raw_of(45));
  CHECK(rig.present(3) == 2548);
  CHECK(rig.present(2) == 2048);  // no hand on it
  rig.step_ms(1000);
  CHECK(rig.present(1) == raw_of(90));
  CHECK(rig.present(3) == 3048);
  const auto state = rig.result(R"({"cmd":"hand"})");
  REQUIRE(state.size() == 2);
  CHECK(state[0]["joint"] == "shoulder_pan");
  CHECK(state[0]["source"] == "file");
  CHECK(state[0]["ended"] == true);
  CHECK(state[0]["value"] == 90.0);
}

TEST_CASE("hand.play with loop and speed plays the trajectory again, faster", "[control][hand]") {
  ArmRig rig;
  rig.add_trajectory("back-and-forth.csv",
                     "time,gripper:raw\n"
                     "0,2048\n"
                     "1,2548\n"
                     "2,2048\n");
  rig.result(
      R"({"cmd":"hand.play","file":"back-and-forth.csv","loop":true,"speed":2,"interpolation":"linear"})");
  rig.step_ms(250);  // trajectory time 0.5 s
  CHECK(rig.present(6) == 2298);
  rig.step_ms(1000);  // 2.5 s: the second pass, 0.5 s in
  CHECK(rig.present(6) == 2298);
  CHECK(rig.result(R"({"cmd":"hand"})")[0]["ended"] == false);
}

TEST_CASE("A trajectory the port cannot play is refused naming the file, the line and the reason",
          "[control][hand]") {
  ArmRig rig;
  rig.add_trajectory("unknown.csv", "# a comment\ntime,shoulder_pan,elbow\n0,0,0\n");
  CHECK(rig.error(R"({"cmd":"hand.play","file":"unknown.csv"})") ==
        "unknown.csv: line 2: no joint \"elbow\" on port arm (its joints: shoulder_pan, "
        "shoulder_lift, elbow_flex, wrist_flex, wrist_roll, gripper; or a servo ID: 1, 2, 3, 4, "
        "5, 6)");
  rig.add_trajectory("too-far.csv", "time,gripper\n0,0\n1,50\n2,120\n");
  CHECK(rig.error(R"({"cmd":"hand.play","file":"too-far.csv"})") ==
        "too-far.csv: line 4: gripper 120° is outside its range -10 ~ 100°");
  rig.add_trajectory("same.csv", "time,gripper,6\n0,0,0\n");
  CHECK(rig.error(R"({"cmd":"hand.play","file":"same.csv"})") ==
        "same.csv: line 1: columns \"gripper\" and \"6\" are the same servo, 6");
  CHECK(rig.error(R"({"cmd":"hand.play","file":"unknown.csv","speed":0})") ==
        "\"speed\" must be more than 0");
  // Nothing was started.
  CHECK(rig.result(R"({"cmd":"hand"})").empty());
}

TEST_CASE("hand.sweep takes each joint through its whole range and back to the middle",
          "[control][hand]") {
  ArmRig rig;
  const auto swept = rig.result(R"({"cmd":"hand.sweep","speed_deg_s":100})");
  CHECK(swept["origin"] == "sweep");
  std::map<int, std::pair<std::int64_t, std::int64_t>> seen;
  const int duration_ms = static_cast<int>(swept["duration_s"].get<double>() * 1000) + 20;
  for (int ms = 0; ms <= duration_ms; ms += 10) {
    rig.step_ms(10);
    for (int id = 1; id <= 6; ++id) {
      const std::int64_t p = rig.present(id);
      auto& [low, high] = seen.try_emplace(id, p, p).first->second;
      low = std::min(low, p);
      high = std::max(high, p);
    }
  }
  for (int id = 1; id <= 5; ++id) {
    CHECK(seen[id].first == raw_of(-100));
    CHECK(seen[id].second == raw_of(100));
    CHECK(rig.present(id) == 2048);
  }
  CHECK(seen[6].first == raw_of(-10));
  CHECK(seen[6].second == raw_of(100));
  CHECK(rig.present(6) == raw_of(45));
}

TEST_CASE("hand.sweep to the middle brings every joint to the middle of its range and stops",
          "[control][hand]") {
  ArmRig rig;
  const auto moved = rig.result(R"({"cmd":"hand.sweep","to":"middle","order":"together"})");
  rig.step_ms(static_cast<int>(moved["duration_s"].get<double>() * 1000) + 10);
  CHECK(rig.present(1) == 2048);
  CHECK(rig.present(6) == raw_of(45));
  CHECK(rig.error(R"({"cmd":"hand.sweep","to":"end"})") ==
        "\"to\" must be \"middle\" (only to the middle of each range), got \"end\"");
}

TEST_CASE("hand.move eases one joint to a place, and hand.stop lets go", "[control][hand]") {
  ArmRig rig;
  rig.result(R"({"cmd":"hand.move","joint":"wrist_flex","position":30,"duration_s":0.5})");
  rig.step_ms(250);
  CHECK(rig.present(4) == raw_of(15));
  rig.step_ms(300);
  CHECK(rig.present(4) == raw_of(30));
  // A second move starts from where the first left the hand.
  rig.result(R"({"cmd":"hand.move","joint":4,"position":2048,"units":"raw","duration_s":0.2})");
  rig.step_ms(300);
  CHECK(rig.present(4) == 2048);
  CHECK(rig.error(R"({"cmd":"hand.move","joint":"wrist_flex","position":150})") ==
        "wrist_flex 150° is outside its range -100 ~ 100°");
  CHECK(rig.error(R"({"cmd":"hand.move","joint":"nose","position":1})") ==
        "no joint \"nose\" on port arm (its joints: shoulder_pan, shoulder_lift, elbow_flex, "
        "wrist_flex, wrist_roll, gripper; or a servo ID: 1, 2, 3, 4, 5, 6)");
  const auto stopped = rig.result(R"({"cmd":"hand.stop","joints":["wrist_flex"]})");
  CHECK(stopped["released"].size() == 1);
  CHECK(rig.result(R"({"cmd":"hand"})").empty());
}

TEST_CASE("Hand requests are checked whole as scenario steps", "[control][hand]") {
  ArmRig rig;
  rig.add_trajectory("unknown.csv", "time,elbow\n0,0\n");
  CHECK(dxlemu::control::Api::check(rig.target, nlohmann::ordered_json::parse(
                                                    R"({"cmd":"hand.play","file":"unknown.csv"})"))
            .value_or("")
            .starts_with("unknown.csv: line 1: no joint \"elbow\""));
  CHECK_FALSE(
      dxlemu::control::Api::check(
          rig.target, nlohmann::ordered_json::parse(R"({"cmd":"hand.sweep","order":"together"})"))
          .has_value());
}
