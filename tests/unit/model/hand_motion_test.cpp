// A hand on a servo's shaft (model/motion/hand.hpp, docs/hands.md): a torque-off shaft follows it
// exactly; a torque-on one feels it as a load up to the hand's force, which Present Current,
// Overload and the rest of the motion model see.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus_write.hpp"
#include "model/servo.hpp"
#include "shipped_model.hpp"

namespace dxlemu::test::hand_motion {

using model::Grip;
using model::Servo;

constexpr std::int64_t kTurnPulses = 4096;
constexpr std::int64_t kCurrentPositionMode = 5;
constexpr std::int64_t kHwOverload = 0x20;

sim::SimTime at_ms(double ms) {
  return sim::SimTime{
      std::chrono::duration_cast<sim::SimDuration>(std::chrono::duration<double, std::milli>(ms))};
}

/// A hand that moves at constant speed from `from` (pulses) at `start_ms` to `to` at `end_ms`,
/// then holds there.
class RampHand : public model::Hand {
 public:
  RampHand(double from, double to, double start_ms, double end_ms, double force_nm)
      : from_(from), to_(to), start_(at_ms(start_ms)), end_(at_ms(end_ms)), force_(force_nm) {}

  std::optional<Grip> grip(sim::SimTime t) const override {
    if (t <= start_) {
      return Grip{from_, 0, force_};
    }
    if (t >= end_) {
      return Grip{to_, 0, force_};
    }
    const double share =
        std::chrono::duration<double>(t - start_) / std::chrono::duration<double>(end_ - start_);
    const double span_ms = std::chrono::duration<double, std::milli>(end_ - start_).count();
    return Grip{from_ + (to_ - from_) * share, (to_ - from_) / span_ms, force_};
  }
  bool still_from(sim::SimTime t) const override { return t >= end_; }

 private:
  double from_;
  double to_;
  sim::SimTime start_;
  sim::SimTime end_;
  double force_;
};

/// One servo on a hand-advanced clock.
struct HandRig {
  explicit HandRig(const std::string& model) : servo(test::shipped_model(model), 1) {}

  Servo servo;
  sim::SimTime now{};

  void to_ms(double ms) {
    now = at_ms(ms);
    servo.advance_to(now);
  }
  std::uint8_t write(const std::string& key, std::int64_t value) {
    servo.advance_to(now);
    return test::bus_write(servo, key, value);
  }
  std::int64_t get(const std::string& key) const { return servo.table().get(key); }
  void hand(double from, double to, double start_ms, double end_ms,
            double force_nm = model::kDefaultHandForceNm) {
    servo.motion().set_hand(std::make_shared<RampHand>(from, to, start_ms, end_ms, force_nm));
  }
};

}  // namespace dxlemu::test::hand_motion

// Qualified names: unity builds put this file beside others with names of their own.
namespace hand_motion = dxlemu::test::hand_motion;
using hand_motion::HandRig;

TEST_CASE("A torque-off shaft follows a hand exactly, tick by tick", "[model][hand]") {
  HandRig rig("xm430-w350");
  rig.hand(1000, 3000, 0, 1000);
  for (int ms = 100; ms <= 1000; ms += 100) {
    rig.to_ms(ms);
    CHECK(rig.get("present_position") == 1000 + 2 * ms);
  }
  rig.to_ms(1500);
  CHECK(rig.get("present_position") == 3000);
  CHECK(rig.get("present_velocity") == 0);
  CHECK(rig.get("present_current") == 0);
}

TEST_CASE("A hand moves the shaft, not the reading: Homing Offset still shifts Present Position",
          "[model][hand]") {
  HandRig rig("xm430-w350");
  REQUIRE(rig.write("homing_offset", 100) == 0);
  rig.hand(2048, 2048, 0, 0);
  rig.to_ms(10);
  CHECK(rig.get("present_position") == 2148);
}

TEST_CASE("A hand takes the shaft the short way round to the angle it holds", "[model][hand]") {
  HandRig rig("xm430-w350");
  rig.hand(4000, 4000, 0, 0);
  rig.to_ms(10);
  REQUIRE(rig.get("present_position") == 4000);
  // 10 and 4106 are the same angle: the hand goes 202 pulses forward across the seam, not
  // 3990 back.
  rig.hand(10 + 2 * hand_motion::kTurnPulses, 10 + 2 * hand_motion::kTurnPulses, 10, 10);
  rig.to_ms(200);
  CHECK(rig.get("present_position") == 4106);
}

TEST_CASE("A torque-on servo holds against a weak hand and shows its push as current",
          "[model][hand]") {
  HandRig rig("xm430-w350");
  REQUIRE(rig.write("torque_enable", 1) == 0);
  const std::int64_t held = rig.get("present_position");
  // 1 N·m towards higher positions, well within the XM430-W350's 4.1 N·m.
  rig.hand(static_cast<double>(held) + 1000, static_cast<double>(held) + 1000, 0, 0, 1.0);
  rig.to_ms(200);
  CHECK(std::abs(rig.get("present_position") - held) <= 1);
  // The motor pushes back: 1 N·m at 4.1 N·m / 2.3 A is 0.56 A, 208 units of 2.69 mA.
  CHECK(std::abs(rig.get("present_current") + 208) <= 2);
  CHECK(rig.get("hardware_error_status") == 0);
}

TEST_CASE("A hand stronger than the servo moves it and the servo overloads", "[model][hand]") {
  HandRig rig("xm430-w350");
  REQUIRE(rig.write("torque_enable", 1) == 0);
  const std::int64_t held = rig.get("present_position");
  rig.hand(static_cast<double>(held), static_cast<double>(held) + 1000, 0, 500, 10.0);
  rig.to_ms(600);
  CHECK(rig.get("present_position") > held + 900);
  rig.to_ms(5000);
  CHECK((rig.get("hardware_error_status") & hand_motion::kHwOverload) != 0);
  CHECK(rig.get("torque_enable") == 0);
  // Shut down, the shaft is free: the hand now has it exactly.
  CHECK(rig.get("present_position") == held + 1000);
}

TEST_CASE("A hand squeezes a gripper held by Goal Current in Current-based Position mode",
          "[model][hand]") {
  HandRig rig("xl330-m077");
  REQUIRE(rig.write("operating_mode", hand_motion::kCurrentPositionMode) == 0);
  REQUIRE(rig.write("goal_current", 30) == 0);
  REQUIRE(rig.write("torque_enable", 1) == 0);
  const std::int64_t open = rig.get("present_position");
  rig.hand(static_cast<double>(open), static_cast<double>(open) - 600, 0, 300);
  rig.to_ms(500);
  // The trigger gives way (the grip is much stronger than 30 mA of an XL330) and springs back...
  CHECK(rig.get("present_position") < open - 550);
  CHECK(std::abs(rig.get("present_current")) <= 30);
  CHECK(rig.get("present_current") >= 28);
  // ... once the hand lets go.
  rig.servo.motion().set_hand(nullptr);
  rig.to_ms(3000);
  CHECK(std::abs(rig.get("present_position") - open) <= 2);
  // Holding at Goal Current is what the mode is for: no Overload, however long.
  CHECK(rig.get("hardware_error_status") == 0);
}

TEST_CASE("A blocked shaft does not move in a hand", "[model][hand]") {
  HandRig rig("xm430-w350");
  dxlemu::model::Conditions blocked = rig.servo.motion().conditions();
  blocked.blocked = true;
  rig.servo.motion().set_conditions(blocked);
  const std::int64_t start = rig.get("present_position");
  rig.hand(static_cast<double>(start), static_cast<double>(start) + 500, 0, 100);
  rig.to_ms(200);
  CHECK(rig.get("present_position") == start);
}

TEST_CASE("A shaft at rest in a still hand rests, and a moving hand keeps it ticking",
          "[model][hand]") {
  HandRig rig("xm430-w350");
  rig.hand(1000, 2000, 0, 100);
  rig.to_ms(50);
  CHECK_FALSE(rig.servo.motion().resting());
  rig.to_ms(300);
  CHECK(rig.servo.motion().resting());
  CHECK(rig.get("present_position") == 2000);
  // A new hand wakes it.
  rig.hand(2000, 2500, 300, 400);
  rig.to_ms(350);
  CHECK(rig.get("present_position") == 2250);
}
