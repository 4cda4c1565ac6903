// Item value encodings beyond DYNAMIXEL's: a model-level big-endian byte order and per-item
// sign-magnitude (docs/model-format.md "Value encodings"), as FEETECH servos store them. The
// models are synthetic (the test model with FEETECH-style items), except in the last test, which
// loads the FEETECH files of models/feetech/ (docs/feetech.md "Models").
#include <catch2/catch.hpp>

#include <algorithm>

#include "app/daemon/bus_state.hpp"
#include "model/table/control_table.hpp"
#include "model/table/item_encoding.hpp"
#include "shipped_model.hpp"
#include "table_access.hpp"
#include "test_model.hpp"

using namespace dxlemu;
using model::ByteOrder;
using model::ControlTable;
using model::TableError;
using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

namespace {

using test::read;
using test::write;

// The test model with sign-magnitude items: Position offset (bit 11, EEPROM), Running speed
// (bit 15), Present load (bit 10, read-only, at rest -5) and PWM open-loop speed (bit 10,
// -1000 ~ 1000), in `order`.
json feetech_style(const std::string& order) {
  json j = test::test_model_json();
  j["byte_order"] = order;
  auto add = [&](json item) { j["items"].push_back(std::move(item)); };
  add({{"key", "position_offset"},
       {"name", "Position offset"},
       {"address", 2},
       {"size", 2},
       {"access", "RW"},
       {"area", "EEPROM"},
       {"initial", 0},
       {"sign_bit", 11}});
  add({{"key", "running_speed"},
       {"name", "Running speed"},
       {"address", 36},
       {"size", 2},
       {"access", "RW"},
       {"area", "RAM"},
       {"initial", 0},
       {"sign_bit", 15}});
  add({{"key", "present_load"},
       {"name", "Present load"},
       {"address", 38},
       {"size", 2},
       {"access", "R"},
       {"area", "RAM"},
       {"initial", -5},
       {"sign_bit", 10}});
  add({{"key", "pwm_speed"},
       {"name", "PWM open-loop speed"},
       {"address", 48},
       {"size", 2},
       {"access", "RW"},
       {"area", "RAM"},
       {"initial", 1000},
       {"sign_bit", 10},
       {"min", -1000},
       {"max", 1000}});
  return j;
}

std::shared_ptr<const model::ModelSpec> feetech_model(const std::string& order) {
  return test::test_model(feetech_style(order));
}

// The error a modified FEETECH-style model raises, as "POINTER: REASON".
std::string feetech_refusal(const std::function<void(json&)>& change) {
  json j = feetech_style("little");
  change(j);
  try {
    model::model_from_json(j, "bad.json");
  } catch (const model::ModelError& e) {
    CHECK(e.origin() == "bad.json");
    return e.pointer() + ": " + e.reason();
  }
  return "accepted";
}

json& item(json& j, const std::string& key) {
  return test::item_json(j, key);
}

model::ItemSpec sign_magnitude(std::uint8_t size, std::uint8_t bit) {
  model::ItemSpec item;
  item.size = size;
  item.sign_bit = bit;
  return item;
}

}  // namespace

TEST_CASE("Byte order: little puts the lowest byte first, big the highest", "[model][encoding]") {
  Bytes two(2);
  model::pack(ByteOrder::Little, 0x1234, two);
  CHECK(two == Bytes{0x34, 0x12});
  model::pack(ByteOrder::Big, 0x1234, two);
  CHECK(two == Bytes{0x12, 0x34});
  CHECK(model::unpack(ByteOrder::Big, Bytes{0x12, 0x34}) == 0x1234);
  CHECK(model::unpack(ByteOrder::Little, Bytes{0x12, 0x34}) == 0x3412);
  CHECK(model::unpack(ByteOrder::Big, Bytes{0x01, 0x02, 0x03, 0x04}) == 0x01020304);
  CHECK(model::unpack(ByteOrder::Little, Bytes{0x01, 0x02, 0x03, 0x04}) == 0x04030201);
}

TEST_CASE("Sign-magnitude values round-trip through their bytes in both byte orders",
          "[model][encoding]") {
  for (const ByteOrder order : {ByteOrder::Little, ByteOrder::Big}) {
    for (const std::uint8_t bit :
         {std::uint8_t{7}, std::uint8_t{10}, std::uint8_t{11}, std::uint8_t{15}}) {
      const model::ItemSpec item = sign_magnitude(bit < 8 ? 1 : 2, bit);
      const std::int64_t top = (std::int64_t{1} << bit) - 1;
      CHECK(model::representable_range(item).min == -top);
      CHECK(model::representable_range(item).max == top);
      for (const std::int64_t v :
           {std::int64_t{0}, std::int64_t{1}, std::int64_t{-1}, top, -top, top / 3, -top / 3}) {
        Bytes bytes(item.size);
        model::encode_value(item, order, v, bytes);
        CHECK(model::decode_value(item, order, bytes) == v);
      }
    }
  }
  // The SDK's WritePosEx: -Position with bit 15 set.
  Bytes bytes(2);
  model::encode_value(sign_magnitude(2, 15), ByteOrder::Little, -2048, bytes);
  CHECK(bytes == Bytes{0x00, 0x88});
  model::encode_value(sign_magnitude(2, 10), ByteOrder::Big, -5, bytes);
  CHECK(bytes == Bytes{0x04, 0x05});
}

TEST_CASE("Sign-magnitude decoding: -0 reads 0, bits above the sign bit count as magnitude",
          "[model][encoding]") {
  const model::ItemSpec load = sign_magnitude(2, 10);
  CHECK(model::decode_value(load, ByteOrder::Little, Bytes{0x00, 0x04}) == 0);  // "-0"
  CHECK(model::decode_value(load, ByteOrder::Little, Bytes{0x05, 0x04}) == -5);
  // Bit 11 set: beyond the representable 1023, so the range check refuses it.
  CHECK(model::decode_value(load, ByteOrder::Little, Bytes{0x05, 0x0C}) == -(0x0805));
  CHECK(model::decode_value(load, ByteOrder::Little, Bytes{0x05, 0x08}) == 0x0805);
  // Two's complement is unchanged.
  model::ItemSpec twos;
  twos.size = 2;
  twos.is_signed = true;
  CHECK(model::decode_value(twos, ByteOrder::Big, Bytes{0xFF, 0xFB}) == -5);
}

TEST_CASE("A big-endian table serves and takes every multi-byte item high byte first",
          "[model][encoding]") {
  ControlTable t(feetech_model("big"));
  CHECK(t.spec().byte_order == ByteOrder::Big);
  CHECK(read(t, 0, 2) == Bytes{0x10, 0x92});  // Model Number 4242
  CHECK(t.raw_value(0, 2) == 4242);
  CHECK(read(t, 28, 4) == Bytes{0x00, 0x00, 0x08, 0x00});  // Goal Position 2048
  CHECK(read(t, 32, 4) == Bytes{0xFF, 0xFF, 0xFF, 0xFB});  // two's complement -5
  CHECK(read(t, 38, 2) == Bytes{0x04, 0x05});              // sign-magnitude -5, bit 10
  REQUIRE(write(t, 28, {0x00, 0x00, 0x0F, 0xFF}) == TableError::None);
  CHECK(t.get("goal_position") == 4095);
  REQUIRE(write(t, 36, {0x81, 0x2C}) == TableError::None);
  CHECK(t.get("running_speed") == -300);
  t.set("running_speed", 1000);
  CHECK(read(t, 36, 2) == Bytes{0x03, 0xE8});
  CHECK(t.encoded(t.index("pwm_speed"), -1000) == Bytes{0x07, 0xE8});
  // Range checks happen on the decoded value: 0x1000 big-endian is 4096, above 4095.
  CHECK(write(t, 28, {0x00, 0x00, 0x10, 0x00}) == TableError::DataRange);
  // A Protocol 1.0 partial write changes the byte it covers: the low byte is the second.
  REQUIRE(write(t, 29, {0x00, 0x00, 0x01}, wire::Protocol::V1) == TableError::None);
  CHECK(t.get("goal_position") == 1);
}

TEST_CASE("A little-endian table stores sign-magnitude values low byte first",
          "[model][encoding]") {
  ControlTable t(feetech_model("little"));
  CHECK(t.spec().byte_order == ByteOrder::Little);
  CHECK(read(t, 0, 2) == Bytes{0x92, 0x10});
  CHECK(read(t, 38, 2) == Bytes{0x05, 0x04});
  REQUIRE(write(t, 36, {0x00, 0x88}) == TableError::None);
  CHECK(t.get("running_speed") == -2048);
  REQUIRE(write(t, 2, {0xFF, 0x0F}) == TableError::None);  // bit 11 and 2047
  CHECK(t.get("position_offset") == -2047);
}

TEST_CASE("Sign-magnitude items are range-checked on the decoded value", "[model][encoding]") {
  ControlTable t(feetech_model("little"));
  // -1000 and 1000 are the ends of PWM open-loop speed's range; -1001 and 1001 are outside.
  CHECK(write(t, 48, {0xE8, 0x07}) == TableError::None);
  CHECK(t.get("pwm_speed") == -1000);
  CHECK(write(t, 48, {0xE9, 0x07}) == TableError::DataRange);
  CHECK(write(t, 48, {0xE9, 0x03}) == TableError::DataRange);
  CHECK(t.get("pwm_speed") == -1000);  // a refused write changes nothing
  // Bits above the sign bit make the magnitude too large for any range: refused.
  CHECK(write(t, 2, {0x01, 0x10}) == TableError::DataRange);
  CHECK(t.get("position_offset") == 0);
  // "-0" is accepted as 0 and reads back as written.
  REQUIRE(write(t, 36, {0x00, 0x80}) == TableError::None);
  CHECK(t.get("running_speed") == 0);
  CHECK(read(t, 36, 2) == Bytes{0x00, 0x80});
  // Device side writes +0 without the sign bit, and refuses what the encoding cannot hold.
  t.set("running_speed", 0);
  CHECK(read(t, 36, 2) == Bytes{0x00, 0x00});
  CHECK(ControlTable::fits(*t.spec().find("running_speed"), -32767));
  CHECK_FALSE(ControlTable::fits(*t.spec().find("running_speed"), -32768));
  CHECK_FALSE(ControlTable::fits(*t.spec().find("present_load"), 1024));
  CHECK_THROWS_AS(t.set("present_load", -1024), std::invalid_argument);
}

TEST_CASE("A state file keeps sign-magnitude EEPROM values by value", "[model][encoding]") {
  for (const std::string order : {"little", "big"}) {
    ControlTable t(feetech_model(order));
    t.set("position_offset", -1234);
    const app::ServoState state = app::capture_state(t);
    const auto saved = std::find_if(state.eeprom.begin(), state.eeprom.end(),
                                    [](const auto& kv) { return kv.first == "position_offset"; });
    REQUIRE(saved != state.eeprom.end());
    CHECK(saved->second == -1234);
    ControlTable restored(feetech_model(order));
    app::restore_state(restored, state, "state.json", "/ports/p/0");
    CHECK(restored.get("position_offset") == -1234);
    CHECK(read(restored, 2, 2) == read(t, 2, 2));
  }
}

TEST_CASE("The loader reads byte_order and sign_bit, with the encoding's full range by default",
          "[model][encoding][loader]") {
  CHECK(test::test_model()->byte_order == ByteOrder::Little);  // absent: little
  const auto spec = feetech_model("big");
  const model::ItemSpec& speed = *spec->find("running_speed");
  REQUIRE(speed.sign_bit);
  CHECK(*speed.sign_bit == 15);
  CHECK_FALSE(speed.is_signed);
  CHECK(speed.min == -32767);
  CHECK(speed.max == 32767);
  CHECK(spec->find("present_load")->min == -1023);
  CHECK(spec->find("present_load")->initial == -5);
  CHECK(spec->find("pwm_speed")->max == 1000);
}

TEST_CASE("The loader refuses bad byte orders, sign bits and sign-magnitude ranges",
          "[model][encoding][loader]") {
  CHECK(feetech_refusal([](json& j) { j["byte_order"] = "middle"; }) ==
        "/byte_order: must be \"little\" or \"big\", got \"middle\"");
  CHECK(feetech_refusal([](json& j) { j["byte_order"] = 1; }) == "/byte_order: must be a string");
  CHECK(feetech_refusal([](json& j) { item(j, "running_speed")["sign_bit"] = 16; }) ==
        "/items/22/sign_bit: must be 1 ~ 15 for a 2-byte item, got 16");
  CHECK(feetech_refusal([](json& j) { item(j, "running_speed")["sign_bit"] = 0; }) ==
        "/items/22/sign_bit: must be 1 ~ 15 for a 2-byte item, got 0");
  CHECK(feetech_refusal([](json& j) { item(j, "present_load")["signed"] = true; }) ==
        "/items/23/sign_bit: cannot be given with \"signed\": true (sign-magnitude or two's "
        "complement, not both)");
  CHECK(feetech_refusal([](json& j) { item(j, "present_load")["min"] = -1024; }) ==
        "/items/23/min: must be between -1023 and 1023, got -1024");
  CHECK(feetech_refusal([](json& j) { item(j, "present_load")["initial"] = 1024; }) ==
        "/items/23/initial: must be between -1023 and 1023, got 1024");
  CHECK(feetech_refusal([](json& j) { item(j, "pwm_speed")["initial"] = -1001; }) ==
        "/items/24/initial: value -1001 is outside the item's range");
  CHECK(feetech_refusal([](json& j) { item(j, "running_speed")["sign_bit"] = "15"; }) ==
        "/items/22/sign_bit: must be an integer");
}

TEST_CASE("The loader names an unknown protocol and the ones it knows", "[model][loader]") {
  CHECK(feetech_refusal([](json& j) { j["protocols"] = {"canbus"}; }) ==
        "/protocols/0: unknown protocol \"canbus\" (known: 1, 2, \"feetech\", \"modbus\")");
  CHECK(feetech_refusal([](json& j) { j["protocols"] = {3}; }) ==
        "/protocols/0: must be between 1 and 2, got 3");
  // A DYNAMIXEL family speaks no FEETECH, and the reverse (docs/feetech.md "One maker per port").
  CHECK(feetech_refusal([](json& j) { j["protocols"] = {"feetech"}; }) ==
        "/protocols/0: a model of the ROBOTIS family \"x\" cannot speak FEETECH");
  CHECK(feetech_refusal([](json& j) { j["family"] = "sts"; }) ==
        "/protocols/0: a model of the FEETECH family \"sts\" cannot speak Protocol 2.0");
}

TEST_CASE("The FEETECH model files load as shipped", "[model][encoding][feetech]") {
  for (const std::string name : {"sts3215", "sts3250", "sm8512bl", "scs0009", "hls3625m"}) {
    INFO(name);
    ControlTable t(test::shipped_model("feetech/" + name));
    CHECK(t.spec().protocols == std::vector{wire::Protocol::Feetech});
    CHECK(t.spec().maker() == model::Maker::Feetech);
    CHECK(t.spec().byte_order == (name == "scs0009" ? ByteOrder::Big : ByteOrder::Little));
    std::vector<std::uint8_t> model_number;
    REQUIRE(t.bus_read(3, 2, model_number).ok());
    CHECK(model::unpack(t.spec().byte_order, model_number) == t.spec().model_number);
  }
  // HLS's address 7 is its Secondary ID: no return delay item, which FEETECH models may lack.
  CHECK_FALSE(test::shipped_model("feetech/hls3625m")->find("return_delay_time"));
  ControlTable sts(test::shipped_model("feetech/sts3215"));
  CHECK(read(sts, 3, 2) == Bytes{0x09, 0x03});  // 777: the ST3215 spreadsheet's 9 and 3
  REQUIRE(write(sts, 42, {0x00, 0x88}, wire::Protocol::Feetech) == TableError::None);
  CHECK(sts.get("goal_position") == -2048);
  REQUIRE(write(sts, 31, {0xFF, 0x0F}, wire::Protocol::Feetech) == TableError::None);
  CHECK(sts.get("position_offset") == -2047);  // lerobot's Homing_Offset, sign bit 11
  CHECK(write(sts, 31, {0x00, 0x10}, wire::Protocol::Feetech) == TableError::DataRange);
  ControlTable scs(test::shipped_model("feetech/scs0009"));
  CHECK(read(scs, 3, 2) == Bytes{0x05, 0x04});  // 1284, high byte first
  REQUIRE(write(scs, 42, {0x01, 0xFF}, wire::Protocol::Feetech) == TableError::None);
  CHECK(scs.get("goal_position") == 511);
  CHECK(read(scs, 56, 2) == Bytes{0x02, 0x00});  // Present position 512 at rest
}

TEST_CASE("refusal_bits: FEETECH models only, never a bit FEETECH defines",
          "[model][loader][feetech]") {
  const auto as_feetech = [](json& j) {
    j["family"] = "sts";
    j["protocols"] = {"feetech"};
  };
  CHECK(feetech_refusal([](json& j) {
          j["refusal_bits"] = {{"checksum", 16}};
        }) == "/refusal_bits: is a setting of FEETECH models only");
  CHECK(feetech_refusal([&](json& j) {
          as_feetech(j);
          j["refusal_bits"] = {{"range", 8}};
        }) ==
        "/refusal_bits/range: uses a bit FEETECH defines for a hardware error (1, 2, 4, 8, "
        "32 are taken)");
  CHECK(feetech_refusal([&](json& j) {
          as_feetech(j);
          j["refusal_bits"] = {{"angle", 64}};
        }).rfind("/refusal_bits/angle: ", 0) == 0);
  json j = feetech_style("little");
  as_feetech(j);
  j["refusal_bits"] = {{"range", 0x80}};
  const model::ModelSpec spec = model::model_from_json(j, "ft.json");
  // The keys not given are the family's.
  CHECK(spec.refusals() == model::Refusals{.checksum = wire::kSilentRefusal,
                                           .instruction = wire::kSilentRefusal,
                                           .read = wire::kSilentRefusal,
                                           .range = {.silent = false, .bit = 0x80}});
}

TEST_CASE("A FEETECH model may lack return_delay_time, a DYNAMIXEL one may not",
          "[model][loader][feetech]") {
  json j = feetech_style("little");
  auto& items = j["items"];
  items.erase(std::remove_if(items.begin(), items.end(),
                             [](const json& item) { return item["key"] == "return_delay_time"; }),
              items.end());
  CHECK_THROWS_WITH(model::model_from_json(j, "x.json"),
                    Catch::Contains("has no item \"return_delay_time\""));
  j["family"] = "hls";
  j["protocols"] = {"feetech"};
  CHECK_FALSE(model::model_from_json(j, "hls.json").find("return_delay_time"));
}
