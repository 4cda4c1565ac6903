// The control table enforces what real servos enforce on bus reads and writes, and a refused write
// changes nothing (docs/control-table.md). These tests use the small test model.
#include <catch2/catch.hpp>

#include "model/table/control_table.hpp"
#include "table_access.hpp"
#include "test_model.hpp"

using namespace dxlemu;
using model::ControlTable;
using model::TableError;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

using test::read;
using test::write;

Bytes le32(std::int64_t v) {
  return test::le(v, 4);
}

}  // namespace

TEST_CASE("A new table holds every initial value, little-endian, signed where declared",
          "[model][table]") {
  ControlTable t(test::test_model());
  CHECK(read(t, 0, 2) == Bytes{0x92, 0x10});  // 4242
  CHECK(t.get("goal_position") == 2048);
  CHECK(t.get("present_velocity") == -5);
  CHECK(read(t, 32, 4) == Bytes{0xFB, 0xFF, 0xFF, 0xFF});
  CHECK(t.get("goal_pwm") == 885);  // copied from PWM Limit at power-on
}

TEST_CASE("Reads span items and reserved bytes, and a read past the end is an Access error",
          "[model][table]") {
  ControlTable t(test::test_model());
  // 2..6 are reserved: they read as 0; the read may end inside ID's neighbour items.
  CHECK(read(t, 0, 8) == Bytes{0x92, 0x10, 0, 0, 0, 0, 0, 0x01});
  CHECK(read(t, 29, 1) == Bytes{0x08});  // the second byte of Goal Position 2048
  Bytes out = {0xAA};
  const auto r = t.bus_read(58, 3, out);
  CHECK(r.error == TableError::Access);
  CHECK(out.empty());
}

TEST_CASE("Writes to read-only items or reserved addresses are Access errors", "[model][table]") {
  ControlTable t(test::test_model());
  CHECK(write(t, 0, {0x01, 0x00}) == TableError::Access);
  CHECK(write(t, 32, le32(1)) == TableError::Access);
  CHECK(write(t, 2, {0x00}) == TableError::Access);
  CHECK(write(t, 60, {0x00}) == TableError::Access);
  // A block write that runs from a writable item into a reserved byte fails as a whole.
  CHECK(write(t, 9, {0x05, 0x00}) == TableError::Access);
  CHECK(t.get("return_delay_time") == 250);
}

TEST_CASE("A 2.0 write covering part of a multi-byte item is a Data Length error, 1.0 allows it",
          "[model][table]") {
  ControlTable t(test::test_model());
  CHECK(write(t, 28, {0x00, 0x01}) == TableError::DataLength);
  CHECK(t.get("goal_position") == 2048);
  CHECK(write(t, 28, {0x00, 0x04}, Protocol::V1) == TableError::None);
  CHECK(t.get("goal_position") == 1024);
}

TEST_CASE("Values outside the range or the allowed values are Data Range errors",
          "[model][table]") {
  ControlTable t(test::test_model());
  CHECK(write(t, 7, {253}) == TableError::DataRange);
  CHECK(write(t, 7, {252}) == TableError::None);
  CHECK(write(t, 11, {2}) == TableError::DataRange);
  CHECK(write(t, 11, {16}) == TableError::None);
  CHECK(write(t, 28, le32(4096)) == TableError::DataRange);
}

TEST_CASE("Values beyond their limit item are Data Limit errors", "[model][table]") {
  ControlTable t(test::test_model());
  REQUIRE(write(t, 16, le32(3000)) == TableError::None);  // Max Position Limit
  CHECK(write(t, 28, le32(3001)) == TableError::DataLimit);
  CHECK(write(t, 28, le32(3000)) == TableError::None);
  REQUIRE(write(t, 12, {100, 0}) == TableError::None);  // PWM Limit 100 bounds Goal PWM to +-100
  CHECK(write(t, 26, {0x9B, 0xFF}) == TableError::DataLimit);  // -101
  CHECK(write(t, 26, {0x9C, 0xFF}) == TableError::None);       // -100
  CHECK(t.get("goal_pwm") == -100);
  CHECK(write(t, 26, {101, 0}) == TableError::DataLimit);
}

TEST_CASE("A limit item written in the same packet bounds with its new value", "[model][table]") {
  ControlTable t(test::test_model());
  // Max Position Limit (16..19), Min Position Limit (20..23), Torque Enable (24), reserved (25):
  // write the limits and check Goal Position separately.
  Bytes limits = le32(1000);
  const Bytes min = le32(10);
  limits.insert(limits.end(), min.begin(), min.end());
  REQUIRE(write(t, 16, limits) == TableError::None);
  CHECK(write(t, 28, le32(1001)) == TableError::DataLimit);
  CHECK(write(t, 28, le32(9)) == TableError::DataLimit);
}

TEST_CASE("EEPROM items refuse writes while torque is on (X, MX 2.0, XL-320, P, PRO)",
          "[model][table]") {
  ControlTable t(test::test_model());
  REQUIRE(write(t, 24, {1}) == TableError::None);
  CHECK(t.eeprom_locked());
  CHECK(write(t, 7, {5}) == TableError::Locked);
  CHECK(write(t, 28, le32(100)) == TableError::None);  // RAM stays writable
  REQUIRE(write(t, 24, {0}) == TableError::None);
  CHECK(write(t, 7, {5}) == TableError::None);
}

TEST_CASE("A refused write changes nothing, even the items before the bad one", "[model][table]") {
  ControlTable t(test::test_model());
  // Max Position Limit then Min Position Limit = 5000 (out of range): neither is written.
  Bytes data = le32(2000);
  const Bytes bad = le32(5000);
  data.insert(data.end(), bad.begin(), bad.end());
  int writes = 0;
  t.on_write("max_position_limit", [&](std::size_t, std::int64_t, std::int64_t) { ++writes; });
  CHECK(write(t, 16, data) == TableError::DataRange);
  CHECK(t.get("max_position_limit") == 4095);
  CHECK(writes == 0);
  CHECK(t.check_write(16, data, Protocol::V2).error == TableError::DataRange);
}

TEST_CASE("Hooks: writes report old and new values", "[model][table]") {
  ControlTable t(test::test_model());
  std::vector<std::int64_t> seen;
  t.on_write("goal_position", [&](std::size_t, std::int64_t old_value, std::int64_t new_value) {
    seen = {old_value, new_value};
  });
  REQUIRE(write(t, 28, le32(300)) == TableError::None);
  CHECK(seen == std::vector<std::int64_t>{2048, 300});
}

TEST_CASE("Validators add rules that refuse a write before anything is committed",
          "[model][table]") {
  ControlTable t(test::test_model());
  t.add_validator("goal_position", [](std::size_t, std::int64_t v) {
    return v == 1234 ? model::TableResult::fail(TableError::DataRange, "watchdog expired")
                     : model::TableResult{};
  });
  const auto r = t.bus_write(28, le32(1234), Protocol::V2);
  CHECK(r.error == TableError::DataRange);
  CHECK(r.detail == "watchdog expired");
  CHECK(t.get("goal_position") == 2048);
}

TEST_CASE("Indirect Data reads and writes the mapped addresses under their items' rules",
          "[model][table]") {
  ControlTable t(test::test_model());
  // Map Indirect Data 1..4 to Goal Position (28..31).
  for (std::uint16_t i = 0; i < 4; ++i) {
    REQUIRE(write(t, static_cast<std::uint16_t>(40 + 2 * i),
                  {static_cast<std::uint8_t>(28 + i), 0}) == TableError::None);
  }
  CHECK(read(t, 50, 4) == le32(2048));
  CHECK(write(t, 50, le32(1000)) == TableError::None);
  CHECK(t.get("goal_position") == 1000);
  CHECK(t.get("indirect_data_1") == 0);  // the data item itself holds nothing
  // The target's rules apply: a partial 2.0 write through indirect data, an out-of-range value.
  CHECK(write(t, 50, {0x01, 0x02}) == TableError::DataLength);
  CHECK(write(t, 50, le32(5000)) == TableError::DataRange);
  CHECK(t.get("goal_position") == 1000);
}

TEST_CASE("Indirect Data mapped to a read-only item refuses writes and reads it",
          "[model][table]") {
  ControlTable t(test::test_model());
  REQUIRE(write(t, 40, {59, 0}) == TableError::None);  // Indirect Data 1 -> Present Temperature
  CHECK(read(t, 50, 1) == Bytes{25});
  CHECK(write(t, 50, {30}) == TableError::Access);
  CHECK(write(t, 40, {60, 0}) == TableError::DataRange);  // outside the address range
}

TEST_CASE("Device-side set bypasses access rules but not the item's width", "[model][table]") {
  ControlTable t(test::test_model());
  t.set("present_velocity", -300);
  CHECK(t.get("present_velocity") == -300);
  CHECK_THROWS_AS(t.set("id", 256), std::invalid_argument);
  CHECK_THROWS_AS(t.get("no_such_item"), std::out_of_range);
}

TEST_CASE("Power-on restores RAM and a factory reset restores EEPROM too", "[model][table]") {
  ControlTable t(test::test_model());
  REQUIRE(write(t, 7, {9}) == TableError::None);
  REQUIRE(write(t, 28, le32(77)) == TableError::None);
  t.load_initial(false);
  CHECK(t.get("id") == 9);
  CHECK(t.get("goal_position") == 2048);
  t.load_initial(true);
  CHECK(t.get("id") == 1);
}

TEST_CASE("An EEPROM lock rule can be replaced (2XL430: both axes must be off)", "[model][table]") {
  ControlTable t(test::test_model());
  bool other_axis_on = true;
  t.set_eeprom_lock([&] { return t.get("torque_enable") != 0 || other_axis_on; });
  CHECK(write(t, 7, {5}) == TableError::Locked);
  other_axis_on = false;
  CHECK(write(t, 7, {5}) == TableError::None);
}

TEST_CASE("Protocol 1.0 families lock EEPROM with Lock, which stays set until power-on",
          "[model][table]") {
  nlohmann::json j = test::test_model_json();
  j["family"] = "ax";
  j["items"].push_back({{"key", "lock"},
                        {"name", "Lock"},
                        {"address", 25},
                        {"size", 1},
                        {"access", "RW"},
                        {"area", "RAM"},
                        {"initial", 0},
                        {"min", 0},
                        {"max", 1}});
  ControlTable t(test::test_model(j));
  REQUIRE(write(t, 24, {1}, Protocol::V1) ==
          TableError::None);  // torque on does not lock AX EEPROM
  CHECK(write(t, 7, {5}, Protocol::V1) == TableError::None);
  REQUIRE(write(t, 25, {1}, Protocol::V1) == TableError::None);
  CHECK(write(t, 7, {6}, Protocol::V1) == TableError::Locked);
  CHECK(write(t, 25, {0}, Protocol::V1) == TableError::Locked);
  t.load_initial(false);
  CHECK(write(t, 7, {6}, Protocol::V1) == TableError::None);
}

TEST_CASE("Refusals map to 2.0 error numbers and 1.0 error bits", "[model][table]") {
  using wire::StatusError;
  namespace v1 = wire::v1_error;
  const std::vector<std::tuple<TableError, StatusError, std::uint8_t>> expected = {
      {TableError::None, StatusError::None, 0},
      {TableError::Access, StatusError::Access, v1::kRange},
      {TableError::DataLength, StatusError::DataLength, v1::kRange},
      {TableError::DataRange, StatusError::DataRange, v1::kRange},
      {TableError::DataLimit, StatusError::DataLimit, v1::kRange},
      {TableError::AngleLimit, StatusError::DataLimit, v1::kAngleLimit},
  };
  for (const auto& [error, v2, bits] : expected) {
    CHECK(model::v2_status_error(error) == v2);
    CHECK(model::v1_error_bits(error) == bits);
  }
}
