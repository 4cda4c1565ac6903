// Every live reading of every model in models/ (catalog.json) reads at rest, a few ms after
// power-on, what the page says a real servo reads: rules by what the item means, so a model added
// later is covered; a live item no rule knows fails, naming it, so that no reading is added
// without deciding its rest value (docs/motion.md "Values at rest").
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "model/motion/motion_items.hpp"
#include "model/servo.hpp"
#include "model/spec/model_loader.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
using model::ItemSpec;
using model::Servo;

namespace {

// How long after power-on the readings are taken: a few motion ticks.
constexpr auto kSettle = std::chrono::milliseconds(5);
// Every model powers on in a room at 25 °C (the converter's Present Temperature).
constexpr double kRoomC = 25;
// A supply within this share of the nominal voltage is one the servo is specified for: the
// e-Manual's Input Voltage ranges reach about 20 % either side of the recommended voltage (AX
// 9 ~ 12 V around 11.1 V, MX 10 ~ 14.8 V around 12 V, RX-28 12 ~ 18.5 V around 14.8 V).
constexpr double kSupplySpread = 0.2;
// The voltage items count 0.1 V unless their unit says otherwise.
constexpr double kDefaultVoltUnit = 0.1;
// Protocol 1.0 Present Speed / Present Load: bits 0 ~ 9 are the magnitude, bit 10 the direction.
constexpr std::int64_t kV1DirectionEncoded = 2047;
constexpr std::int64_t kV1Magnitude = 1023;
constexpr std::int64_t kRealtimeTickWrap = 32768;

/// The items that are live readings: those the motion model writes, and every read-only RAM
/// item (whatever a bus write cannot set is the device's to report).
std::vector<std::size_t> live_items(const model::ModelSpec& spec) {
  std::set<std::size_t> live;
  for (const std::size_t i : model::MotionItems(spec).readings()) {
    live.insert(i);
  }
  for (std::size_t i = 0; i < spec.items.size(); ++i) {
    if (spec.items[i].access == model::Access::ReadOnly && spec.items[i].area == model::Area::Ram) {
      live.insert(i);
    }
  }
  return {live.begin(), live.end()};
}

/// The number a unit string starts with ("0.1 [V]" -> 0.1), or `otherwise`.
double unit_figure(const std::string& unit, double otherwise) {
  std::smatch m;
  static const std::regex figure(R"(^\s*(?:about\s*)?([0-9.]+))");
  return std::regex_search(unit, m, figure) ? std::stod(m[1].str()) : otherwise;
}

/// The quantity an item's value stands for: the magnitude of a 1.0 direction-bit encoding.
std::int64_t magnitude(const ItemSpec& item, std::int64_t value) {
  const bool direction_bit = !item.is_signed && item.max == kV1DirectionEncoded;
  return direction_bit ? value & kV1Magnitude : value;
}

/// What a servo at rest shows in one live item; `value` is what the emulated one shows.
struct Reading {
  const Servo& servo;
  const ItemSpec& item;
  std::int64_t value = 0;
  sim::SimTime now{};
};

/// What a real servo reads at rest, for the items whose key matches `key`.
struct RestRule {
  const char* meaning;
  std::regex key;
  std::function<void(const Reading&)> check;
};

void position_as_set(const Reading& r) {
  // Where the shaft was put: the model's power-on position, within the item's range.
  CHECK(r.value == r.item.initial);
  if (r.item.max > r.item.min) {
    CHECK(r.value >= r.item.min);
    CHECK(r.value <= r.item.max);
  }
}

void trajectory_at_shaft(const Reading& r) {
  CHECK(r.value == r.servo.table().get("present_position"));
}

void zero(const Reading& r) {
  CHECK(magnitude(r.item, r.value) == 0);
}

void no_current(const Reading& r) {
  // 0 A in the reading's encoding: 0 for Present Current, the offset zero of the 1.0 readings
  // (MX Current 2048, EX-106+ Sensed Current 512).
  const std::int64_t zero_a = r.servo.spec().motion.current_zero;
  CHECK(r.value == zero_a);
  // An unsigned reading must show both directions: its zero lies strictly inside its range.
  if (!r.item.is_signed) {
    const std::int64_t top =
        r.item.max > r.item.min ? r.item.max : (std::int64_t{1} << (8 * r.item.size)) - 1;
    CHECK(zero_a > r.item.min);
    CHECK(zero_a < top);
  }
}

void supply(const Reading& r) {
  const double unit = unit_figure(r.item.unit, kDefaultVoltUnit);
  const double supply_v = r.servo.motion().conditions().supply_v;
  CHECK(r.value == std::llround(supply_v / unit));
  const double nominal = r.servo.motion().params().nominal_voltage_v;
  INFO("supply " << supply_v << " V, nominal " << nominal << " V");
  CHECK(std::abs(supply_v - nominal) <= kSupplySpread * nominal);
}

void ambient(const Reading& r) {
  CHECK(r.servo.motion().conditions().ambient_c == kRoomC);
  CHECK(r.value == std::llround(kRoomC));
}

void motion_under_way(const Reading& r) {
  // Nothing moves at rest. DYNAMIXEL-Y's Moving Status also says whether Present Position lies
  // within Min/Max Position Limit (bit 6, Position In Range): at rest it does.
  const bool range_bit =
      r.servo.spec().traits().moving_status_motion_and_range && r.item.key == "moving_status";
  CHECK(r.value == (range_bit ? 0x40 : 0));
}

void torque_off_without_error(const Reading& r) {
  // DYNAMIXEL-Y Controller State: 2, Inverter OFF ("Torque OFF state"): Torque Enable is 0.
  CHECK(r.servo.table().get("torque_enable") == 0);
  CHECK(r.value == 2);
}

void milliseconds_since_power_on(const Reading& r) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(r.now.time_since_epoch());
  CHECK(r.value == ms.count() % kRealtimeTickWrap);
}

const std::vector<RestRule>& rest_rules() {
  static const std::vector<RestRule> rules = {
      {"the shaft's position", std::regex("present_position"), position_as_set},
      {"the trajectory's position", std::regex("position_trajectory"), trajectory_at_shaft},
      {"a velocity", std::regex("present_velocity|present_speed|velocity_trajectory"), zero},
      {"a torque or output share", std::regex("present_load|present_pwm"), zero},
      {"a current", std::regex("present_current|current|sensed_current"), no_current},
      {"the supply voltage", std::regex("present_(input_)?voltage"), supply},
      {"a temperature", std::regex("present_(\\w+_)?temperature"), ambient},
      {"the millisecond counter", std::regex("realtime_tick"), milliseconds_since_power_on},
      {"motion under way", std::regex("moving|moving_status"), motion_under_way},
      {"a hardware error", std::regex("hardware_error_status|error_code(_history_\\d+)?"), zero},
      {"the controller's state", std::regex("controller_state"), torque_off_without_error},
      {"a registered instruction", std::regex("registered(_instruction)?"), zero},
      {"a stored Control Table Backup", std::regex("backup_ready"), zero},
  };
  return rules;
}

const RestRule* rule_for(const std::string& key) {
  for (const RestRule& rule : rest_rules()) {
    if (std::regex_match(key, rule.key)) {
      return &rule;
    }
  }
  return nullptr;
}

}  // namespace

TEST_CASE("Every live reading of every model reads at rest what a real servo reads",
          "[model][motion][rest]") {
  const auto models = test::catalog_models();
  REQUIRE_FALSE(models.empty());
  for (const auto& spec : models) {
    Servo servo(spec, spec->default_id);
    const sim::SimTime now{kSettle};
    servo.advance_to(now);
    for (const std::size_t i : live_items(*spec)) {
      const ItemSpec& item = spec->items[i];
      INFO(spec->name << ": " << item.name << " (" << item.key << ", address " << item.address
                      << ") reads " << servo.table().get(i));
      const RestRule* rule = rule_for(item.key);
      if (rule == nullptr) {
        FAIL_CHECK(
            "a live item with no rest rule in rest_values_test.cpp: decide what a servo "
            "at rest reads there");
        continue;
      }
      INFO("rule: " << rule->meaning);
      rule->check({servo, item, servo.table().get(i), now});
    }
  }
}

TEST_CASE("A live item without a rest rule fails the audit", "[model][motion][rest]") {
  CHECK(rule_for("present_position") != nullptr);
  CHECK(rule_for("present_inverter_temperature") != nullptr);
  CHECK(rule_for("error_code_history_16") != nullptr);
  CHECK(rule_for("error_code_history") == nullptr);
  CHECK(rule_for("present_flux_capacitance") == nullptr);
}

namespace {

/// A Protocol 1.0 current item encodes the motor's current around its zero: `zero` at rest, and
/// `zero` + amps / `amps_per_unit` once a blocked shaft with torque on makes the motor draw.
void check_current_encoding(const char* model_name, const char* key, std::int64_t zero,
                            double amps_per_unit) {
  INFO(model_name << ": " << key);
  Servo servo(test::shipped_model(model_name), 1);
  servo.advance_to(sim::SimTime{kSettle});
  CHECK(servo.table().get(key) == zero);
  model::Conditions blocked = servo.motion().conditions();
  blocked.blocked = true;
  servo.motion().set_conditions(blocked);
  servo.device_write(servo.table().index("goal_position"), 3000);
  servo.advance_to(sim::SimTime{std::chrono::milliseconds(200)});
  const double amps = servo.motion().motor().current_a;
  REQUIRE(amps > 1);
  CHECK(servo.table().get(key) == zero + std::llround(amps / amps_per_unit));
}

}  // namespace

TEST_CASE("MX 1.0 Current encodes the actual current around 2048 (4.5 mA per unit)",
          "[model][motion][rest]") {
  for (const char* name : {"mx-64", "mx-106"}) {
    check_current_encoding(name, "current", 2048, 0.0045);
  }
}

TEST_CASE("EX-106+ Sensed Current keeps its 512 zero and 10 mA unit", "[model][motion][rest]") {
  check_current_encoding("ex-106+", "sensed_current", 512, 0.01);
}
