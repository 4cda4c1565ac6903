// Firmware variants (docs/model-format.md, docs/families.md): an XL330/XC330 runs the V53 table by
// default and the older 20-item Indirect layout as firmware 52, and each reports its own
// firmware, so a client that picks its table by the Firmware Version it reads gets the right one.
#include <catch2/catch.hpp>

#include <memory>

#include "bus_rig.hpp"
#include "model/spec/firmware_variant.hpp"
#include "model/spec/model_loader.hpp"
#include "wire/hex.hpp"

using namespace dxlemu;
using test::BusRig;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::shared_ptr<const model::ModelSpec> with_firmware(const std::string& name,
                                                      std::uint8_t version) {
  auto spec = model::model_for_firmware(*test::shipped_model(name), version);
  REQUIRE(spec.has_value());
  return std::make_shared<const model::ModelSpec>(std::move(*spec));
}

// The status of `packet` sent to the rig's one servo, as describe() prints it.
std::string ask(BusRig& rig, const wire::Instruction& instruction) {
  rig.link.clear();
  rig.send({Protocol::V2, 1, instruction});
  rig.run();
  const auto& d = rig.link.deliveries();
  return d.size() == 1 ? test::status_text(d[0].bytes) : "not one reply";
}

}  // namespace

TEST_CASE("XL330 firmware 52 has 20 Indirect items, addresses at 168, data at 208", "[bus]") {
  const auto spec = with_firmware("xl330-m288", 52);
  CHECK(spec->name == "xl330-m288@52");
  CHECK(spec->firmware_version == 52);
  REQUIRE(spec->indirect.size() == 1);
  CHECK(spec->indirect[0].address == 168);
  CHECK(spec->indirect[0].data == 208);
  CHECK(spec->indirect[0].count == 20);
  REQUIRE(spec->find("indirect_address_1") != nullptr);
  CHECK(spec->find("indirect_address_1")->address == 168);
  CHECK(spec->find("indirect_address_1")->initial == 208);
  CHECK(spec->find("indirect_address_20")->address == 206);
  CHECK(spec->find("indirect_address_20")->max == 227);
  CHECK(spec->find("indirect_data_1")->address == 208);
  CHECK(spec->find("indirect_data_20")->address == 227);
  CHECK(spec->find("indirect_address_21") == nullptr);
  CHECK(spec->find("indirect_data_21") == nullptr);
  CHECK(spec->table_size() == 228);
  // Everything else is the default firmware's.
  const auto base = test::shipped_model("xl330-m288");
  CHECK(spec->items.size() == base->items.size() - 16);
  CHECK(spec->find("present_position")->address == base->find("present_position")->address);
}

TEST_CASE("XL330 firmware 52 maps Indirect Data 1 to the address Indirect Address 1 holds",
          "[bus]") {
  BusRig rig;
  const auto spec = with_firmware("xl330-m288", 52);
  auto& servo = rig.bus.add_servo(std::make_unique<model::Servo>(spec, 1));
  servo.table().set("present_position", 0x01020304);
  const auto position = spec->find("present_position")->address;  // 132
  for (std::uint16_t i = 0; i < 4; ++i) {
    const auto target = static_cast<std::uint16_t>(position + i);
    CHECK(ask(rig, wire::Write{static_cast<std::uint16_t>(168 + 2 * i),
                               {static_cast<std::uint8_t>(target & 0xFF),
                                static_cast<std::uint8_t>(target >> 8)}}) == "id=1 error=0x00");
  }
  const std::string direct = ask(rig, wire::Read{position, 4});
  CHECK(direct == "id=1 error=0x00 params=04 03 02 01");
  CHECK(ask(rig, wire::Read{208, 4}) == direct);
  CHECK(ask(rig, wire::Read{208, 1}) == "id=1 error=0x00 params=04");
}

TEST_CASE("XL330 firmware 52 reports 52 in Ping and Firmware Version, the default 53 or more",
          "[bus]") {
  BusRig old_firmware;
  old_firmware.bus.add_servo(std::make_unique<model::Servo>(with_firmware("xl330-m288", 52), 1));
  CHECK(ask(old_firmware, wire::Ping{}) == "id=1 error=0x00 params=B0 04 34");  // 1200, 52
  CHECK(ask(old_firmware, wire::Read{6, 1}) == "id=1 error=0x00 params=34");

  BusRig today;
  auto& servo = today.add("xl330-m288", 1);
  CHECK(servo.spec().firmware_version >= 53);
  CHECK(servo.table().get("firmware_version") == servo.spec().firmware_version);
  REQUIRE(servo.spec().indirect.size() == 1);
  CHECK(servo.spec().indirect[0].data == 224);
  CHECK(servo.spec().indirect[0].count == 28);
  CHECK(servo.spec().find("indirect_data_1")->address == 224);
  CHECK(ask(today, wire::Read{6, 1}) ==
        "id=1 error=0x00 params=" +
            wire::to_hex(std::vector<std::uint8_t>{servo.spec().firmware_version}));
}

TEST_CASE("Every XL330/XC330 has the firmware 52 variant, XM335-T323 none", "[bus]") {
  for (const char* name :
       {"xl330-m077", "xl330-m288", "xc330-m181", "xc330-m288", "xc330-t181", "xc330-t288"}) {
    CAPTURE(name);
    const auto base = test::shipped_model(name);
    CHECK(base->firmware_version >= 53);
    REQUIRE(base->firmware_variants.size() == 1);
    CHECK(base->firmware_variants[0].firmware_version == 52);
    CHECK(with_firmware(name, 52)->find("indirect_data_1")->address == 208);
  }
  const auto xm335 = test::shipped_model("xm335-t323");
  CHECK(xm335->firmware_variants.empty());
  CHECK_FALSE(model::model_for_firmware(*xm335, 52).has_value());
  CHECK(model::model_for_firmware(*xm335, xm335->firmware_version)->name == "xm335-t323");
}
