// The access-rule matrix on shipped models of each kind: an X model, an MX 1.0 model, XL-320,
// AX-12A and the dual-axis 2XL430 (docs/control-table.md).
#include <catch2/catch.hpp>

#include "model/table/control_table.hpp"
#include "model/table/dual_axis.hpp"
#include "shipped_model.hpp"
#include "table_access.hpp"

using namespace dxlemu;
using model::ControlTable;
using model::TableError;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::shared_ptr<const model::ModelSpec> shipped(const std::string& name) {
  return test::shipped_model(name);
}

using test::le;
using test::write;

}  // namespace

TEST_CASE("XM430-W350 access rules", "[model][matrix]") {
  ControlTable t(shipped("xm430-w350"));
  const auto v2 = Protocol::V2;
  CHECK(write(t, 0, le(1, 2), v2) == TableError::Access);          // Model Number is read-only
  CHECK(write(t, 14, {0}, v2) == TableError::Access);              // reserved
  CHECK(write(t, 116, le(100, 2), v2) == TableError::DataLength);  // half of Goal Position
  CHECK(write(t, 7, {253}, v2) == TableError::DataRange);          // ID 0 ~ 252
  CHECK(write(t, 11, {2}, v2) == TableError::DataRange);           // no Operating Mode 2
  REQUIRE(write(t, 48, le(3000, 4), v2) == TableError::None);      // Max Position Limit
  CHECK(write(t, 116, le(3001, 4), v2) == TableError::DataLimit);
  CHECK(write(t, 100, le(-886, 2), v2) == TableError::DataRange);  // Goal PWM beyond its range
  REQUIRE(write(t, 36, le(500, 2), v2) == TableError::None);       // PWM Limit 500
  CHECK(write(t, 100, le(-501, 2), v2) == TableError::DataLimit);
  REQUIRE(write(t, 64, {1}, v2) == TableError::None);  // torque on locks EEPROM
  CHECK(write(t, 7, {2}, v2) == TableError::Locked);
  CHECK(write(t, 116, le(2000, 4), v2) == TableError::None);
  std::vector<std::uint8_t> out;
  CHECK(t.bus_read(660, 4, out).error == TableError::Access);  // past the end (661)
  CHECK(t.bus_read(0, 662, out).ok());
}

TEST_CASE("XM430-W350 indirect data maps Present Position across both blocks", "[model][matrix]") {
  ControlTable t(shipped("xm430-w350"));
  // Indirect Address 1..4 (168..175) -> Present Position 132..135; Indirect Address 29 (578) ->
  // 146.
  for (std::uint16_t i = 0; i < 4; ++i) {
    REQUIRE(write(t, static_cast<std::uint16_t>(168 + 2 * i), le(132 + i, 2), Protocol::V2) ==
            TableError::None);
  }
  REQUIRE(write(t, 578, le(146, 2), Protocol::V2) == TableError::None);
  t.set("present_position", -70000);
  t.set("present_temperature", 37);
  std::vector<std::uint8_t> out;
  REQUIRE(t.bus_read(224, 4, out).ok());
  CHECK(out == le(-70000, 4));
  REQUIRE(t.bus_read(634, 1, out).ok());
  CHECK(out == Bytes{37});
  CHECK(write(t, 224, le(5, 4), Protocol::V2) == TableError::Access);  // read-only target
  CHECK(write(t, 168, le(63, 2), Protocol::V2) ==
        TableError::DataRange);  // EEPROM cannot be mapped
}

TEST_CASE("MX-28 (Protocol 1.0) access rules", "[model][matrix]") {
  ControlTable t(shipped("mx-28"));
  const auto v1 = Protocol::V1;
  CHECK(write(t, 0, le(1, 2), v1) == TableError::Access);
  CHECK(write(t, 10, {0}, v1) == TableError::Access);  // reserved
  CHECK(write(t, 3, {254}, v1) == TableError::DataRange);
  CHECK(write(t, 3, {253}, v1) == TableError::None);    // 1.0 IDs go up to 253
  CHECK(write(t, 30, {0x10}, v1) == TableError::None);  // a partial write is allowed in 1.0
  CHECK(t.get("goal_position") == (t.spec().find("goal_position")->initial & 0xFF00) + 0x10);
  REQUIRE(write(t, 24, {1}, v1) == TableError::None);  // torque on does not lock EEPROM ...
  CHECK(write(t, 3, {5}, v1) == TableError::None);
  REQUIRE(write(t, 47, {1}, v1) == TableError::None);  // ... Lock does
  CHECK(write(t, 3, {6}, v1) == TableError::Locked);
  CHECK(write(t, 47, {0}, v1) == TableError::Locked);
}

TEST_CASE("AX-12A access rules", "[model][matrix]") {
  ControlTable t(shipped("ax-12a"));
  const auto v1 = Protocol::V1;
  CHECK(t.get("torque_limit") == t.get("max_torque"));      // Torque Limit starts at Max Torque
  CHECK(write(t, 36, le(0, 2), v1) == TableError::Access);  // Present Position is read-only
  CHECK(write(t, 30, le(1024, 2), v1) == TableError::DataRange);
  CHECK(write(t, 30, le(1023, 2), v1) == TableError::None);
  CHECK(write(t, 45, {0}, v1) == TableError::Access);  // reserved
  REQUIRE(write(t, 47, {1}, v1) == TableError::None);
  CHECK(write(t, 4, {1}, v1) == TableError::Locked);        // Baud Rate locked by Lock
  CHECK(write(t, 34, le(100, 2), v1) == TableError::None);  // RAM stays writable
}

TEST_CASE("XL-320 access rules", "[model][matrix]") {
  ControlTable t(shipped("xl-320"));
  const auto v2 = Protocol::V2;
  CHECK(write(t, 3, {253}, v2) == TableError::DataRange);
  CHECK(write(t, 4, {4}, v2) == TableError::DataRange);  // Baud Rate 0 ~ 3
  CHECK(write(t, 30, {0x00}, v2) == TableError::DataLength);
  REQUIRE(write(t, 24, {1}, v2) == TableError::None);  // XL-320 locks EEPROM with torque
  CHECK(write(t, 3, {2}, v2) == TableError::Locked);
  CHECK(write(t, 37, le(0, 2), v2) == TableError::Access);  // Present Position is read-only
}

TEST_CASE("2XL430-W250: EEPROM needs both axes off, Baud Rate and Protocol Type are shared",
          "[model][matrix]") {
  const auto spec = shipped("2xl430-w250");
  CHECK(spec->axes == 2);
  ControlTable first(spec);
  ControlTable second(spec);
  model::link_axes(first, second);
  const auto v2 = Protocol::V2;
  REQUIRE(write(second, 64, {1}, v2) == TableError::None);  // the other axis's torque on
  CHECK(write(first, 7, {3}, v2) == TableError::Locked);
  REQUIRE(write(second, 64, {0}, v2) == TableError::None);
  CHECK(write(first, 7, {3}, v2) == TableError::None);
  CHECK(second.get("id") == 1);  // IDs are per axis
  CHECK(write(first, 8, {3}, v2) == TableError::None);
  CHECK(second.get("baud_rate") == 3);
  CHECK(write(second, 13, {1}, v2) == TableError::None);
  CHECK(first.get("protocol_type") == 1);
}

TEST_CASE("AX-12A in joint mode refuses a Goal Position outside CW/CCW Angle Limit",
          "[model][matrix]") {
  ControlTable t(shipped("ax-12a"));
  const auto v1 = Protocol::V1;
  REQUIRE(write(t, 6, le(200, 2), v1) == TableError::None);  // CW Angle Limit
  REQUIRE(write(t, 8, le(800, 2), v1) == TableError::None);  // CCW Angle Limit
  const auto refused = t.bus_write(30, le(801, 2), v1);
  CHECK(refused.error == TableError::AngleLimit);
  CHECK(model::v1_error_bits(refused.error) == wire::v1_error::kAngleLimit);
  CHECK(write(t, 30, le(199, 2), v1) == TableError::AngleLimit);
  CHECK(write(t, 30, le(800, 2), v1) == TableError::None);
  // Wheel mode (both limits 0): Goal Position is not bounded by the limits.
  REQUIRE(write(t, 6, le(0, 2), v1) == TableError::None);
  REQUIRE(write(t, 8, le(0, 2), v1) == TableError::None);
  CHECK(write(t, 30, le(900, 2), v1) == TableError::None);
}

TEST_CASE("MX-28 multi-turn mode (both limits 4095) takes any Goal Position in range",
          "[model][matrix]") {
  ControlTable t(shipped("mx-28"));
  const auto v1 = Protocol::V1;
  CHECK(write(t, 30, le(-1, 2), v1) == TableError::AngleLimit);  // joint mode: 0 ~ 4095
  REQUIRE(write(t, 6, le(4095, 2), v1) == TableError::None);
  REQUIRE(write(t, 8, le(4095, 2), v1) == TableError::None);
  CHECK(write(t, 30, le(-20000, 2), v1) == TableError::None);
  CHECK(t.get("goal_position") == -20000);
}

TEST_CASE("XL-320 answers a Goal Position outside its angle limits with Data Limit Error",
          "[model][matrix]") {
  ControlTable t(shipped("xl-320"));
  REQUIRE(write(t, 8, le(600, 2), Protocol::V2) == TableError::None);  // CCW Angle Limit
  const auto refused = t.bus_write(30, le(601, 2), Protocol::V2);
  CHECK(refused.error == TableError::AngleLimit);
  CHECK(model::v2_status_error(refused.error) == wire::StatusError::DataLimit);
}

TEST_CASE("X models have no angle-limit rule on Goal Position", "[model][matrix]") {
  ControlTable t(shipped("xm430-w350"));
  CHECK(write(t, 116, le(4095, 4), Protocol::V2) == TableError::None);
}
