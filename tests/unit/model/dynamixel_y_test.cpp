// DYNAMIXEL-Y (models/ym*.json, family "y"): the rules of its pages and of the Y description blocks
// of ROBOTIS-GIT/emanual (_includes/en/dxl/y/), on a hand-advanced clock. Where the pages are
// silent the servo does what DYNAMIXEL-P does (docs/families.md "DYNAMIXEL-Y").
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "model/servo.hpp"
#include "model/spec/model_loader.hpp"
#include "status_bytes.hpp"
#include "table_access.hpp"

using namespace dxlemu;
namespace fs = std::filesystem;
using model::Servo;

namespace {

using test::kAlert;
using test::kDataRange;
using test::kInPosition;
using test::kResultFail;

const fs::path kModels(DXLEMU_MODELS_DIR);

// Status error numbers (protocol2.md "Status Packet"): the low 7 bits of the error byte.
constexpr std::uint8_t kDataLimit = 0x06;
constexpr std::uint8_t kErrorNumber = 0x7F;

// Controller State(152) and Hybrid Save(170) values.
constexpr std::int64_t kInverterOff = 2;
constexpr std::int64_t kRunning = 5;
constexpr std::int64_t kHwFault = 8;
constexpr std::int64_t kHybridChanged = 0;
constexpr std::int64_t kHybridSaved = 2;

// Moving Status(541) bits.
constexpr std::int64_t kMovingBit = 0x04;
constexpr std::int64_t kPositionInRange = 0x40;

std::shared_ptr<const model::ModelSpec> load(const std::string& name) {
  const fs::path file = kModels / (name + ".json");
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return std::make_shared<const model::ModelSpec>(model::parse_model(s.str(), file.string()));
}

/// One Y servo on a hand-advanced clock, driven by Protocol 2.0 instructions.
struct YBench {
  explicit YBench(const std::string& name = "ym070-210-r051-rh") : servo(load(name), 1) {
    servo.advance_to(now);
  }

  Servo servo;
  sim::SimTime now{std::chrono::milliseconds(5)};

  const model::ItemSpec& item(const std::string& key) const { return *servo.spec().find(key); }

  /// A Write of `key` = `value`; the status error byte.
  std::uint8_t write(const std::string& key, std::int64_t value) {
    const model::ItemSpec& it = item(key);
    std::vector<std::uint8_t> data;
    for (std::size_t i = 0; i < it.size; ++i) {
      data.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i)));
    }
    return servo
        .execute({wire::Protocol::V2, servo.id(), wire::Write{it.address, data}},
                 model::Addressing::Unicast)
        .error;
  }
  /// A Read of `key` over the bus, as a client sees it; `error` gets the status error byte.
  std::int64_t read(const std::string& key, std::uint8_t* error = nullptr) {
    const model::ItemSpec& it = item(key);
    const model::ServoResponse r =
        servo.execute({wire::Protocol::V2, servo.id(), wire::Read{it.address, it.size}},
                      model::Addressing::Unicast);
    if (error != nullptr) {
      *error = r.error;
    }
    REQUIRE(r.params.size() == it.size);
    return test::from_le(r.params, it.is_signed);
  }
  void wait(int ms) {
    now += std::chrono::milliseconds(ms);
    servo.advance_to(now);
  }
  void supply(double volts) {
    model::Conditions c = servo.motion().conditions();
    c.supply_v = volts;
    servo.motion().set_conditions(c);
  }
};

}  // namespace

TEST_CASE("Every DYNAMIXEL-Y model is family y and speaks Protocol 2.0 as its 2.0 model number",
          "[model][y]") {
  const std::vector<std::pair<std::string, int>> numbers = {
      {"ym070-210-m001-rh", 4000}, {"ym070-210-b001-rh", 4010}, {"ym070-210-r051-rh", 4020},
      {"ym070-210-r099-rh", 4030}, {"ym070-210-a051-rh", 4040}, {"ym070-210-a099-rh", 4050},
      {"ym080-230-m001-rh", 4120}, {"ym080-230-b001-rh", 4130}, {"ym080-230-r051-rh", 4140},
      {"ym080-230-r099-rh", 4150}, {"ym080-230-a051-rh", 4160}, {"ym080-230-a099-rh", 4170}};
  for (const auto& [name, number] : numbers) {
    CAPTURE(name);
    YBench b(name);
    CHECK(b.servo.spec().family == model::Family::Y);
    CHECK(b.servo.spec().protocols == std::vector<wire::Protocol>{wire::Protocol::V2});
    CHECK(b.read("model_number") == number);  // not the Modbus number (4041 etc.)
    CHECK(b.read("protocol_type") == 2);
    // The gains and profiles live in the Hybrid area; the Indirect Addresses in EEPROM.
    CHECK(b.item("position_p_gain").area == model::Area::Hybrid);
    CHECK(b.item("profile_time").area == model::Area::Hybrid);
    CHECK(b.item("indirect_address_1").area == model::Area::Eeprom);
  }
}

TEST_CASE("Y Operating Mode takes 0, 1 and 3, each driven by its own goal item", "[model][y]") {
  YBench b;
  CHECK((b.write("operating_mode", 2) & kErrorNumber) == kDataRange);  // no mode 2
  CHECK((b.write("operating_mode", 4) & kErrorNumber) == kDataRange);  // no extended mode
  CHECK(b.read("operating_mode") == 3);

  SECTION("Position Control Mode (3): Goal Position(532), within the position limits") {
    REQUIRE(b.write("torque_enable", 1) == 0);
    REQUIRE(b.write("goal_position", 16000) == 0);
    CHECK(b.read("goal_position") == 16000);
    b.wait(3000);
    CHECK(std::llabs(b.read("present_position") - 16000) <= b.read("in_position_threshold"));
    CHECK((b.read("moving_status") & kInPosition) != 0);
    // Max Position Limit 262,144 bounds Goal Position (and no Extended mode widens it).
    CHECK((b.write("goal_position", 300000) & kErrorNumber) == kDataLimit);
  }
  SECTION("Velocity Control Mode (1): Goal Velocity(528) in 0.01 rev/min") {
    REQUIRE(b.write("operating_mode", 1) == 0);
    REQUIRE(b.write("torque_enable", 1) == 0);
    REQUIRE(b.write("goal_velocity", 1000) == 0);  // 10 rev/min
    b.wait(2000);
    CHECK(b.read("present_velocity") == Approx(1000).margin(20));
    CHECK((b.read("moving_status") & kMovingBit) != 0);
    CHECK(b.read("present_position") > 0);
  }
  SECTION("Current Control Mode (0): Goal Current(526) in 0.01 A") {
    REQUIRE(b.write("operating_mode", 0) == 0);
    REQUIRE(b.write("torque_enable", 1) == 0);
    // Held still, the motor draws the commanded current (free, it would speed up until its
    // back-EMF leaves next to none).
    model::Conditions held = b.servo.motion().conditions();
    held.blocked = true;
    b.servo.motion().set_conditions(held);
    // 1 A: the Y files state no stall torque or current, so the motor model's default standstill
    // cap (1.5 A) applies (docs/motion.md); within it, the reading is the goal.
    REQUIRE(b.write("goal_current", 100) == 0);
    b.wait(200);
    CHECK(b.read("present_current") == Approx(100).margin(1));
    CHECK(b.read("present_velocity") == 0);
    held.blocked = false;
    b.servo.motion().set_conditions(held);
    b.wait(50);
    CHECK(b.read("present_velocity") > 0);
  }
}

TEST_CASE("Y time-based profiles take Profile Time and Profile Acceleration Time, in 0.2 ms",
          "[model][y]") {
  YBench b;
  constexpr std::int64_t kTimeBased = 0x04;  // Drive Mode bit 2
  constexpr std::int64_t kProfileOngoing = 0x02;
  REQUIRE(b.write("drive_mode", kTimeBased) == 0);
  REQUIRE(b.write("profile_time", 5000) == 0);               // 1,000 ms
  REQUIRE(b.write("profile_acceleration_time", 1000) == 0);  // 200 ms
  REQUIRE(b.write("torque_enable", 1) == 0);
  REQUIRE(b.write("goal_position", 100000) == 0);
  // Profile Velocity (39.21 rev/min, about 340 pulses/ms) would be there in about 0.3 s.
  b.wait(600);
  const std::int64_t halfway = b.read("present_position");
  CHECK(halfway > 30000);
  CHECK(halfway < 90000);
  CHECK((b.read("moving_status") & kProfileOngoing) != 0);
  b.wait(500);
  CHECK(std::llabs(b.read("present_position") - 100000) <= b.read("in_position_threshold"));
  CHECK((b.read("moving_status") & kProfileOngoing) == 0);

  SECTION("Profile Time 0 deactivates the profile: the motor goes as fast as it can") {
    REQUIRE(b.write("profile_time", 0) == 0);
    REQUIRE(b.write("goal_position", 0) == 0);
    b.wait(5);
    CHECK((b.read("moving_status") & 0x30) == 0);  // profile type: unused (step)
    b.wait(295);                                   // under a third of the 1,000 ms the profile took
    CHECK((b.read("moving_status") & kProfileOngoing) == 0);
    CHECK(std::llabs(b.read("present_position")) <= b.read("in_position_threshold"));
  }
  SECTION("Velocity Control ramps over Profile Acceleration Time") {
    REQUIRE(b.write("torque_enable", 0) == 0);
    REQUIRE(b.write("operating_mode", 1) == 0);
    REQUIRE(b.write("drive_mode", kTimeBased) == 0);
    REQUIRE(b.write("profile_acceleration_time", 2500) == 0);  // 500 ms
    REQUIRE(b.write("torque_enable", 1) == 0);
    REQUIRE(b.write("goal_velocity", 1000) == 0);
    b.wait(250);
    CHECK(b.read("present_velocity") == Approx(500).margin(30));
    b.wait(400);
    CHECK(b.read("present_velocity") == Approx(1000).margin(20));
  }
}

TEST_CASE("Y Present Input Voltage counts 0.01 V, its limits 0.1 V", "[model][y]") {
  YBench b;
  CHECK(b.read("present_input_voltage") == 2400);  // 24 V
  b.supply(30.55);
  b.wait(10);
  CHECK(b.read("present_input_voltage") == 3055);
  CHECK(b.read("error_code") == 0);  // within Max Voltage Limit 32.0 V (320)
  // Set device-side, the reading moves the supply the servo runs on.
  b.servo.device_write(b.servo.table().index("present_input_voltage"), 2210);
  b.wait(10);
  CHECK(b.servo.motion().conditions().supply_v == Approx(22.1));
}

TEST_CASE("Y Present Motor Temperature is the winding, Present Inverter Temperature stays",
          "[model][y]") {
  YBench b;
  CHECK(b.read("present_motor_temperature") == 25);
  CHECK(b.read("present_inverter_temperature") == 25);
  b.servo.device_write(b.servo.table().index("present_motor_temperature"), 61);
  b.wait(10);
  // Over Motor Temperature Limit (60): Motor Overheating Error (4).
  CHECK(b.read("present_motor_temperature") >= 60);
  CHECK(b.read("error_code") == 4);
  CHECK(b.read("present_inverter_temperature") == 25);
}

TEST_CASE("Y Controller State follows torque and errors", "[model][y]") {
  YBench b;
  CHECK(b.read("controller_state") == kInverterOff);
  REQUIRE(b.write("torque_enable", 1) == 0);
  CHECK(b.read("controller_state") == kRunning);
  REQUIRE(b.write("torque_enable", 0) == 0);
  CHECK(b.read("controller_state") == kInverterOff);
  REQUIRE(b.write("torque_enable", 1) == 0);
  b.supply(12);  // below Min Voltage Limit 16.0 V
  b.wait(10);
  CHECK(b.read("controller_state") == kHwFault);
}

TEST_CASE("Y errors set Error Code, keep a history, turn torque off and raise the Alert bit",
          "[model][y]") {
  YBench b;
  REQUIRE(b.write("torque_enable", 1) == 0);
  b.supply(12);  // Low Voltage Error
  b.wait(10);
  std::uint8_t error = 0;
  CHECK(b.read("error_code", &error) == 2);
  CHECK((error & kAlert) != 0);
  CHECK(b.read("torque_enable") == 0);
  CHECK(b.read("error_code_history_1") == 2);
  CHECK((b.write("torque_enable", 1) & kErrorNumber) == kResultFail);
  b.supply(35);  // Over Voltage Error: the most recent error shows, both are in the history
  b.wait(10);
  CHECK(b.read("error_code") == 1);
  CHECK(b.read("error_code_history_1") == 2);
  CHECK(b.read("error_code_history_2") == 1);
  b.supply(12);  // Low Voltage again: Error Code shows it, the history has it once
  b.wait(10);
  CHECK(b.read("error_code") == 2);
  CHECK(b.read("error_code_history_3") == 0);
  // A reboot at a good supply clears the error; torque can be turned on again.
  b.supply(24);
  b.servo.reboot();
  b.wait(10);
  CHECK(b.read("error_code", &error) == 0);
  CHECK((error & kAlert) == 0);
  CHECK(b.read("controller_state") == kInverterOff);
  CHECK(b.write("torque_enable", 1) == 0);
}

TEST_CASE("Y Hybrid items are written with torque on and kept over a reboot once saved",
          "[model][y]") {
  YBench b;
  const std::int64_t factory = b.read("position_p_gain");
  REQUIRE(b.write("torque_enable", 1) == 0);
  // EEPROM is locked with torque on; the Hybrid area is not.
  CHECK((b.write("moving_threshold", 30) & kErrorNumber) != 0);
  REQUIRE(b.write("position_p_gain", 5000000) == 0);
  CHECK(b.read("hybrid_save") == kHybridChanged);
  // A save request needs torque off.
  CHECK((b.write("hybrid_save", 1) & kErrorNumber) == kResultFail);

  SECTION("unsaved, a reboot restores the saved (factory) value") {
    b.servo.reboot();
    b.wait(10);
    CHECK(b.read("position_p_gain") == factory);
  }
  SECTION("saved, the value survives a reboot; changing it again reads Changed") {
    REQUIRE(b.write("torque_enable", 0) == 0);
    REQUIRE(b.write("hybrid_save", 1) == 0);
    CHECK(b.read("hybrid_save") == kHybridSaved);
    b.servo.reboot();
    b.wait(10);
    CHECK(b.read("position_p_gain") == 5000000);
    REQUIRE(b.write("profile_time", 1000) == 0);
    CHECK(b.read("hybrid_save") == kHybridChanged);
    REQUIRE(b.write("profile_time", 800) == 0);  // back to the saved value
    CHECK(b.read("hybrid_save") == kHybridSaved);
  }
}

TEST_CASE("Y Moving Status says Position In Range and Moving besides the P bits", "[model][y]") {
  YBench b;
  CHECK(b.read("moving_status") == kPositionInRange);
  // A Homing Offset beyond Max Position Limit (262,144) puts Present Position out of range.
  REQUIRE(b.write("homing_offset", 300000) == 0);
  b.wait(10);
  CHECK(b.read("present_position") == 300000);
  CHECK((b.read("moving_status") & kPositionInRange) == 0);
}

TEST_CASE("Y Clear resets the multi-turn position, only while the servo stands still",
          "[model][y]") {
  YBench b;
  const auto clear = [&] {
    return b.servo
        .execute({wire::Protocol::V2, 1, wire::Clear{0x01, {0x44, 0x58, 0x4C, 0x22}}},
                 model::Addressing::Unicast)
        .error;
  };
  constexpr std::int64_t kTurn = 524288;  // pulses per revolution
  REQUIRE(b.write("operating_mode", 1) == 0);
  REQUIRE(b.write("torque_enable", 1) == 0);
  REQUIRE(b.write("goal_velocity", 3000) == 0);  // 30 rev/min: a turn in 2 s
  b.wait(3000);
  CHECK(b.read("present_position") > kTurn);
  // Y has no Moving item; Moving Status bit 2 says it turns.
  CHECK((b.read("moving_status") & kMovingBit) != 0);
  CHECK((clear() & kErrorNumber) == kResultFail);
  REQUIRE(b.write("goal_velocity", 0) == 0);
  b.wait(500);
  REQUIRE((b.read("moving_status") & kMovingBit) == 0);
  CHECK(clear() == 0);
  b.wait(5);
  const std::int64_t position = b.read("present_position");
  CHECK(position >= 0);
  CHECK(position < kTurn);
}

TEST_CASE("Y Realtime Tick counts milliseconds and wraps after 32,767", "[model][y]") {
  YBench b;
  b.wait(995);
  CHECK(b.read("realtime_tick") == 1000);
  b.wait(32768);
  CHECK(b.read("realtime_tick") == 1000);
}

TEST_CASE("Y Bus Watchdog is two bytes, reads -1 after it expires and sets Error Code 18",
          "[model][y]") {
  YBench b;
  REQUIRE(b.write("torque_enable", 1) == 0);   // the watchdog runs while torque is on
  REQUIRE(b.write("bus_watchdog", 100) == 0);  // 2,000 ms
  CHECK(b.servo.bus_watchdog_period() == std::chrono::milliseconds(2000));
  b.servo.expire_bus_watchdog();
  std::uint8_t error = 0;
  CHECK(b.read("bus_watchdog", &error) == -1);
  // Bus Watchdog Error (18) keeps torque on ("Torque ON: Y") and holds the goals.
  CHECK(b.read("error_code") == 18);
  CHECK((error & kAlert) != 0);
  CHECK(b.read("error_code_history_1") == 18);
  CHECK(b.read("torque_enable") == 1);
  CHECK(b.read("controller_state") == kRunning);
  CHECK((b.write("goal_position", 1000) & kErrorNumber) == kDataRange);
  // Writing 0 to Bus Watchdog clears it; the history keeps it.
  REQUIRE(b.write("bus_watchdog", 0) == 0);
  CHECK(b.read("error_code", &error) == 0);
  CHECK((error & kAlert) == 0);
  CHECK(b.read("error_code_history_1") == 18);
  CHECK(b.write("goal_position", 1000) == 0);
}
