// dxlemu clone's scan on an emulated bus, on the virtual clock: what it finds, what it reads,
// that it writes nothing, and the config it makes (docs/robots.md "Cloning a real bus").
#include <catch2/catch.hpp>
#include <variant>

#include "app/config/bus_config.hpp"
#include "app/config/clone_config.hpp"
#include "bus/bus_rig.hpp"
#include "scan/bus_scan.hpp"
#include "shipped_models.hpp"
#include "wire/status_reader.hpp"

namespace dxlemu {
namespace {

using namespace std::chrono_literals;

/// A scan link onto a BusRig: each exchange runs the bus for a while and frames what came.
class RigScanLink final : public scan::ScanLink {
 public:
  explicit RigScanLink(test::BusRig& rig) : rig_(rig) {}
  void set_baud(std::uint32_t bps) override { bps_ = bps; }
  std::vector<wire::StatusPacket> exchange(const wire::InstructionPacket& packet,
                                           std::size_t max_replies,
                                           std::chrono::microseconds timeout) override {
    const std::size_t before = rig_.link.deliveries().size();
    const bool reads = std::holds_alternative<wire::Ping>(packet.instruction) ||
                       std::holds_alternative<wire::Read>(packet.instruction);
    only_reads_ = only_reads_ && reads;
    rig_.send(packet, bps_);
    // Long enough for a broadcast Ping's chain of 2.0 replies.
    rig_.run(timeout + 100ms);
    ++sent_;
    wire::StatusReader reader(packet.protocol);
    std::vector<wire::StatusPacket> replies;
    const auto& deliveries = rig_.link.deliveries();
    for (std::size_t i = before; i < deliveries.size(); ++i) {
      reader.feed(deliveries[i].bytes, deliveries[i].at, replies);
    }
    reader.end_of_write(replies);  // a Modbus response ends at the silence after it
    if (replies.size() > max_replies) {
      replies.resize(max_replies);
    }
    return replies;
  }
  std::size_t sent() const { return sent_; }
  /// Every packet sent was a Ping or a Read.
  bool only_reads() const { return only_reads_; }

 private:
  test::BusRig& rig_;
  std::uint32_t bps_ = 0;
  std::size_t sent_ = 0;
  bool only_reads_ = true;
};

scan::ScanOptions narrow(std::vector<std::uint32_t> bauds) {
  scan::ScanOptions options;
  options.bauds = std::move(bauds);
  options.last_id = 12;
  options.timeout = 5ms;
  return options;
}

std::int64_t eeprom(const scan::FoundServo& servo, const std::string& key) {
  for (const auto& [k, v] : servo.eeprom) {
    if (k == key) {
      return v;
    }
  }
  FAIL("no " << key);
  return 0;
}

}  // namespace

TEST_CASE("A scan finds 2.0 and 1.0 servos at their rates and reads their EEPROM, writing nothing",
          "[app][clone]") {
  test::BusRig rig;
  model::Servo& xm = rig.add("xm430-w350", 3);  // 57600 at the factory
  xm.table().set("homing_offset", -300);
  model::Servo& ax = rig.add("ax-12a", 5);  // 1 Mbit/s at the factory
  ax.table().set("cw_angle_limit", 100);
  RigScanLink link(rig);
  std::vector<std::string> lines;
  const auto found = scan::scan_bus(link, test::shipped_models(), narrow({1'000'000, 57'600}),
                                    [&](const std::string& line) { lines.push_back(line); });
  REQUIRE(found.size() == 2);
  CHECK(found[0].id == 5);
  CHECK(found[0].bps == 1'000'000);
  CHECK(found[0].protocol == wire::Protocol::V1);
  REQUIRE(found[0].spec);
  CHECK(found[0].spec->name == "ax-12a");
  CHECK(eeprom(found[0], "cw_angle_limit") == 100);
  CHECK(found[1].id == 3);
  CHECK(found[1].bps == 57'600);
  CHECK(found[1].protocol == wire::Protocol::V2);
  REQUIRE(found[1].spec);
  CHECK(found[1].spec->name == "xm430-w350");
  CHECK(found[1].firmware == xm.table().get("firmware_version"));
  CHECK(eeprom(found[1], "homing_offset") == -300);
  CHECK(link.only_reads());
  constexpr std::size_t kSweeps = 26;  // IDs 0 ~ 12 at two rates
  CHECK(link.sent() > kSweeps);        // and the reads
  CHECK(!lines.empty());

  const auto config = app::clone_config(found, "/dev/ttyUSB0", "arm", "");
  const auto& servos = config["ports"][0]["servos"];
  REQUIRE(servos.size() == 2);
  CHECK(servos[1]["model"] == "xm430-w350");
  CHECK(servos[1]["id"] == 3);
  // Only what differs from the factory values; the ID is the servo's own field.
  CHECK(servos[1]["items"] == nlohmann::ordered_json{{"homing_offset", -300}});
  CHECK(servos[0]["items"] == nlohmann::ordered_json{{"cw_angle_limit", 100}});
  CHECK(!config["ports"][0].contains("link"));
}

TEST_CASE("A scan tells FEETECH servos from DYNAMIXEL 1.0 by where their model number is",
          "[app][clone][feetech]") {
  test::BusRig rig;
  rig.add("feetech/sts3215", 1);
  rig.add("feetech/scs0009", 2);  // big-endian table
  RigScanLink link(rig);
  scan::ScanOptions options = narrow({1'000'000});
  options.protocols = {wire::Protocol::V1, wire::Protocol::Feetech};
  const auto found =
      scan::scan_bus(link, test::shipped_models(), options, [](const std::string&) {});
  REQUIRE(found.size() == 2);
  REQUIRE(found[0].spec);
  CHECK(found[0].spec->name == "sts3215");
  CHECK(found[0].protocol == wire::Protocol::Feetech);
  CHECK(found[0].model_number == 777);
  REQUIRE(found[1].spec);
  CHECK(found[1].spec->name == "scs0009");
  CHECK(found[1].model_number == 1284);
}

TEST_CASE("A servo of a model the library lacks is reported and left out of the config",
          "[app][clone]") {
  test::BusRig rig;
  // A 1.0 servo's Model Number is read from its table: one the library does not know.
  model::Servo& ax = rig.add("ax-12a", 3);
  ax.table().set("model_number", 4242);
  RigScanLink link(rig);
  std::vector<std::string> lines;
  const auto found = scan::scan_bus(link, test::shipped_models(), narrow({1'000'000}),
                                    [&](const std::string& line) { lines.push_back(line); });
  REQUIRE(found.size() == 1);
  CHECK(found[0].spec == nullptr);
  CHECK(found[0].model_number == 4242);
  CHECK(std::any_of(lines.begin(), lines.end(), [](const std::string& line) {
    return line.find("model number 4242 is not in the model library") != std::string::npos;
  }));
  CHECK(app::clone_config(found, "p", "dxl0", "")["ports"][0]["servos"].empty());
}

TEST_CASE("A scan asked for Modbus RTU reads each address's Model Number, then its EEPROM",
          "[app][clone][modbus]") {
  test::BusRig rig;
  model::Servo& ph = rig.add("ph42-020-s300-r", 5);
  ph.table().set("protocol_type", wire::traits(wire::Protocol::Modbus).type_value);
  ph.table().set("homing_offset", -300);
  ph.table().set("return_delay_time", 10);  // not in the Modbus map: cannot be read
  ph.commit_deferred();
  REQUIRE(ph.protocol() == wire::Protocol::Modbus);
  RigScanLink link(rig);
  scan::ScanOptions options = narrow({57'600});
  options.protocols = {wire::Protocol::V2, wire::Protocol::Modbus};
  std::vector<std::string> lines;
  const auto found = scan::scan_bus(link, test::shipped_models(), options,
                                    [&](const std::string& line) { lines.push_back(line); });
  // 2.0's broadcast Ping finds nobody: the servo speaks Modbus.
  REQUIRE(found.size() == 1);
  CHECK(found[0].protocol == wire::Protocol::Modbus);
  CHECK(found[0].id == 5);
  CHECK(found[0].model_number == ph.spec().model_number);
  CHECK(found[0].firmware == ph.table().get("firmware_version"));
  REQUIRE(found[0].spec);
  CHECK(found[0].spec->name == "ph42-020-s300-r");
  CHECK(eeprom(found[0], "homing_offset") == -300);
  CHECK(eeprom(found[0], "protocol_type") == 10);
  CHECK(std::none_of(found[0].eeprom.begin(), found[0].eeprom.end(),
                     [](const auto& item) { return item.first == "return_delay_time"; }));
  CHECK(link.only_reads());
  CHECK(std::any_of(lines.begin(), lines.end(), [](const std::string& line) {
    return line.find("not in the Modbus RTU map") != std::string::npos;
  }));
  // IDs 1 ~ 12 asked at one rate (0 is Modbus's broadcast address), the 2.0 Ping, the reads.
  CHECK(link.sent() > 13);

  // The config it makes serves the servo on Modbus again.
  const auto config = app::clone_config(found, "/dev/ttyUSB0", "arm", "");
  const auto& servo = config["ports"][0]["servos"][0];
  CHECK(servo["items"]["protocol_type"] == 10);
  CHECK(servo["items"]["homing_offset"] == -300);
  const app::BusConfig parsed =
      app::parse_config(config.dump(), "clone.json", test::shipped_models());
  const auto spec = test::shipped_models().find("ph42-020-s300-r");
  CHECK(app::configured_protocol(parsed.ports[0].servos[0], *spec) == wire::Protocol::Modbus);
}

TEST_CASE("The default scan leaves Modbus RTU out", "[app][clone][modbus]") {
  CHECK(scan::ScanOptions{}.protocols == scan::default_scan_protocols());
  const auto protocols = scan::default_scan_protocols();
  CHECK(std::find(protocols.begin(), protocols.end(), wire::Protocol::Modbus) == protocols.end());
  CHECK(protocols.size() == wire::all_protocols().size() - 1);
  test::BusRig rig;
  model::Servo& ph = rig.add("ph42-020-s300-r", 5);
  ph.table().set("protocol_type", wire::traits(wire::Protocol::Modbus).type_value);
  ph.commit_deferred();
  RigScanLink link(rig);
  CHECK(scan::scan_bus(link, test::shipped_models(), narrow({57'600}), [](const std::string&) {
        }).empty());
}

}  // namespace dxlemu
