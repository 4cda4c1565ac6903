// A port's starting hands (app/config/hand_start.hpp, docs/hands.md "From the command line"):
// --hand SPEC and a config port's "hand" become the hand.play or hand.sweep request the daemon
// runs at start.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <string>

#include "app/config/hand_start.hpp"
#include "model/hand/joint_scale.hpp"
#include "shipped_model.hpp"

namespace dxlemu::test::hand_start {

nlohmann::json request_of(const app::HandStart& start) {
  return nlohmann::json::parse(start.request);
}

std::string refusal_of(const nlohmann::json& value) {
  try {
    app::hand_starts_of_json(value, "arm.json", "/ports/0/hand", ".");
  } catch (const app::ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace dxlemu::test::hand_start

using dxlemu::app::hand_start_of_option;
using dxlemu::app::hand_starts_of_json;
using dxlemu::test::hand_start::refusal_of;
using dxlemu::test::hand_start::request_of;
using nlohmann::json;

TEST_CASE("A --hand FILE with options is a hand.play request", "[app][hand]") {
  const auto start = hand_start_of_option("pick.csv,loop,speed=2,interpolation=linear");
  CHECK(request_of(start) ==
        json::parse(R"({"cmd":"hand.play","file":"pick.csv","loop":true,"speed":2,)"
                    R"("interpolation":"linear"})"));
  CHECK(start.origin == "--hand pick.csv,loop,speed=2,interpolation=linear");
}

TEST_CASE("A --hand sweep is a hand.sweep request", "[app][hand]") {
  CHECK(request_of(hand_start_of_option("sweep,order=together,speed_deg_s=45")) ==
        json::parse(R"({"cmd":"hand.sweep","order":"together","speed_deg_s":45})"));
}

TEST_CASE("A --hand without a file, or with a nameless option, is refused", "[app][hand]") {
  CHECK_THROWS_WITH(hand_start_of_option(""),
                    Catch::Contains("give a trajectory FILE or \"sweep\""));
  CHECK_THROWS_WITH(hand_start_of_option("pick.csv,=2"),
                    "--hand pick.csv,=2: an option without a name (KEY=VALUE)");
}

TEST_CASE("A config port's hand is a SPEC, an object with file or sweep, or an array of them",
          "[app][hand]") {
  const auto starts = hand_starts_of_json(
      json::parse(R"([{"file": "no-such-file.csv", "loop": true}, {"sweep": true}, "sweep"])"),
      "arm.json", "/ports/0/hand", ".");
  REQUIRE(starts.size() == 3);
  CHECK(request_of(starts[0]) ==
        json::parse(R"({"cmd":"hand.play","file":"no-such-file.csv","loop":true})"));
  CHECK(starts[0].origin == "arm.json: /ports/0/hand/0");
  CHECK(request_of(starts[1]) == json::parse(R"({"cmd":"hand.sweep"})"));
  CHECK(request_of(starts[2]) == json::parse(R"({"cmd":"hand.sweep"})"));
  CHECK(refusal_of(json::parse(R"({"loop": true})")) ==
        "arm.json: /ports/0/hand: needs one of \"file\" (a trajectory) or \"sweep\": true");
  CHECK(refusal_of(json::parse("3")).starts_with("arm.json: /ports/0/hand: must be a trajectory"));
  CHECK(refusal_of(json::parse(R"({"sweep": 1})")) ==
        "arm.json: /ports/0/hand/sweep: must be true");
}

TEST_CASE("Degrees count from the middle of the factory position limits", "[app][hand]") {
  using dxlemu::model::JointScale;
  using dxlemu::model::JointUnit;
  const JointScale x = JointScale::of(*dxlemu::test::shipped_model("xm430-w350"));
  CHECK(x.middle == 2048);
  CHECK(x.to_pulses(90, JointUnit::Degrees) == 3072);
  CHECK(x.to_pulses(90, JointUnit::Raw) == 90);
  CHECK(JointScale::of(*dxlemu::test::shipped_model("feetech/sts3215")).middle == 2048);
  const JointScale ax = JointScale::of(*dxlemu::test::shipped_model("ax-12a"));
  CHECK(ax.middle == 512);
  CHECK(ax.from_pulses(512 + 1024.0 / 300 * 30, JointUnit::Degrees) == Approx(30));
  CHECK(JointScale::of(*dxlemu::test::shipped_model("ph54-200-s500-r")).middle == 0);
}
