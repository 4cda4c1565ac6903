// A reading computed from a setting follows the setting on the very next read, with no motion tick
// between (docs/motion.md "Settings the readings follow at once"): Present Position = direction ·
// shaft + Homing Offset (Multi Turn Offset on MX 1.0), and Drive Mode's reverse bit flips the
// Present values' signs. Over every model in models/ that has the items, so every family that
// has them (X, MX(2.0), P, PRO(A), Y: Homing Offset and Drive Mode; PRO: Homing Offset; MX 1.0:
// Multi Turn Offset) is covered, and models added later too.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "model/servo.hpp"
#include "model/spec/model_loader.hpp"
#include "shipped_model.hpp"
#include "table_access.hpp"

using namespace dxlemu;
using model::Servo;

namespace {

constexpr std::int64_t kDriveModeReverse = 0x01;
// External load that back-drives a servo with torque off: well above the 5 % of stall torque that
// holds the shaft (docs/motion.md), below what would spin it at no-load speed.
constexpr double kBackDriveShare = 0.5;

/// One servo on a hand-advanced clock, driven by bus instructions in the protocol it speaks.
struct ReadingBench {
  explicit ReadingBench(std::shared_ptr<const model::ModelSpec> spec) : servo(std::move(spec), 1) {
    servo.advance_to(now);
  }

  Servo servo;
  sim::SimTime now{std::chrono::milliseconds(5)};

  wire::Protocol protocol() const { return servo.protocol().value_or(wire::Protocol::V2); }
  const model::ItemSpec& item(const std::string& key) const { return *servo.spec().find(key); }

  static std::vector<std::uint8_t> encode(const model::ItemSpec& item, std::int64_t value) {
    std::vector<std::uint8_t> data;
    for (std::size_t i = 0; i < item.size; ++i) {
      data.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i)));
    }
    return data;
  }
  std::uint8_t execute(wire::Instruction instruction) {
    return servo
        .execute({protocol(), servo.id(), std::move(instruction)}, model::Addressing::Unicast)
        .error;
  }
  /// A Write of `key` = `value`; the status error byte.
  std::uint8_t write(const std::string& key, std::int64_t value) {
    const model::ItemSpec& it = item(key);
    return execute(wire::Write{it.address, encode(it, value)});
  }
  /// A Read of `key` over the bus, as a client sees it (no time passes).
  std::int64_t read(const std::string& key) {
    const model::ItemSpec& it = item(key);
    const model::ServoResponse r = servo.execute(
        {protocol(), servo.id(), wire::Read{it.address, it.size}}, model::Addressing::Unicast);
    REQUIRE(r.error == 0);
    REQUIRE(r.params.size() == it.size);
    return test::from_le(r.params, it.is_signed);
  }
  /// Lets `ms` of simulated time pass (the motion model catches up, as before an instruction).
  void wait(int ms) {
    now += std::chrono::milliseconds(ms);
    servo.advance_to(now);
  }
};

/// The offset item Present Position adds: Homing Offset, or MX 1.0 Multi Turn Offset.
const char* offset_key(const model::ModelSpec& spec) {
  if (spec.find("homing_offset")) {
    return "homing_offset";
  }
  return spec.find("multi_turn_offset") ? "multi_turn_offset" : nullptr;
}

bool reverses(const model::ModelSpec& spec) {
  return spec.find("drive_mode") && spec.traits().drive_mode_reverses;
}

}  // namespace

TEST_CASE("Present Position shows a new Homing Offset on the very next read, in every family",
          "[model][motion][settings]") {
  std::set<std::string> families;
  for (const auto& spec : test::catalog_models()) {
    const char* offset = offset_key(*spec);
    if (offset == nullptr) {
      continue;
    }
    INFO(spec->name << ": " << offset);
    families.insert(std::string(model::family_name(spec->family)));
    ReadingBench bench(spec);
    const std::int64_t before = bench.read("present_position");
    // Offsets the item accepts (RH-P12-RN(A) takes 0 ~ 1,150 only).
    const model::ItemSpec& item = bench.item(offset);
    const auto accepted = [&](std::int64_t v) { return std::clamp(v, item.min, item.max); };
    for (const std::int64_t homing : {1000, -300, 0, 777}) {
      REQUIRE(bench.write(offset, accepted(homing)) == 0);
      CHECK(bench.read("present_position") == before + accepted(homing));
    }
    // A tick later it is still so (the tick computes the same thing).
    bench.wait(3);
    CHECK(bench.read("present_position") == before + accepted(777));
  }
  CHECK(families == std::set<std::string>{"x", "mx2", "mx1", "p", "pro", "pro_a", "y"});
}

TEST_CASE("Drive Mode's reverse bit shows in Present Position and Velocity on the next read",
          "[model][motion][settings]") {
  std::set<std::string> families;
  for (const auto& spec : test::catalog_models()) {
    if (!reverses(*spec)) {
      continue;
    }
    INFO(spec->name);
    families.insert(std::string(model::family_name(spec->family)));
    ReadingBench bench(spec);
    const char* offset = offset_key(*spec);
    REQUIRE(offset != nullptr);
    REQUIRE(bench.write(offset, 500) == 0);
    // Torque off, a load back-drives the shaft: it turns without the motor.
    model::Conditions load = bench.servo.motion().conditions();
    load.external_load_nm = kBackDriveShare * bench.servo.motion().params().stall_torque_nm;
    bench.servo.motion().set_conditions(load);
    bench.wait(20);
    const std::int64_t forward_velocity = bench.read("present_velocity");
    REQUIRE(forward_velocity > 0);
    const std::int64_t mode = bench.read("drive_mode");
    REQUIRE(bench.write("drive_mode", mode | kDriveModeReverse) == 0);
    // The same shaft, seen the other way round, at once.
    const double shaft = bench.servo.motion().motor().position;
    CHECK(bench.read("present_position") == std::llround(-shaft + 500));
    CHECK(bench.read("present_velocity") == -forward_velocity);
    REQUIRE(bench.write("drive_mode", mode) == 0);
    CHECK(bench.read("present_position") == std::llround(shaft + 500));
    CHECK(bench.read("present_velocity") == forward_velocity);
  }
  CHECK(families == std::set<std::string>{"x", "mx2", "p", "pro_a", "y"});
}

TEST_CASE("Homing Offset through Reg Write and Action shows at once too",
          "[model][motion][settings]") {
  ReadingBench bench(test::shipped_model("xl430-w250"));
  const std::int64_t before = bench.read("present_position");
  const model::ItemSpec& homing = bench.item("homing_offset");
  REQUIRE(bench.execute(wire::RegWrite{homing.address, ReadingBench::encode(homing, -1301)}) == 0);
  CHECK(bench.read("present_position") == before);  // registered, not yet written
  REQUIRE(bench.execute(wire::Action{}) == 0);
  CHECK(bench.read("present_position") == before - 1301);
}

TEST_CASE("A Homing Offset forced in device-side shows in Present Position at once",
          "[model][motion][settings]") {
  ReadingBench bench(test::shipped_model("xl330-m288"));
  REQUIRE(bench.write("torque_enable", 1) == 0);  // EEPROM locked: the bus cannot write it now
  bench.wait(3);
  const std::int64_t before = bench.read("present_position");
  bench.servo.device_write(bench.servo.table().index("homing_offset"), 198);
  CHECK(bench.read("present_position") == before + 198);
}
