// Fault rules as data (docs/faults.md): every action parses and prints back the same, and every
// malformed rule is refused naming the member and the reason.
#include <catch2/catch.hpp>

#include <set>

#include "faults/rule_parser.hpp"

using namespace dxlemu;
using faults::parse_rule;
using faults::RuleError;
using nlohmann::json;

namespace {

/// The JSON pointer and message of the RuleError that parsing `text` throws, as "pointer: reason".
std::string refusal(const std::string& text) {
  try {
    parse_rule(json::parse(text));
  } catch (const RuleError& e) {
    return e.pointer() + ": " + e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("Every action parses and rule_json reads back as the same rule", "[faults]") {
  const std::vector<std::string> rules = {
      R"({"action":"drop_reply","match":{"port":"dxl0","servos":[3],"instruction":"read"},"probability":0.05,"count":10,"after":100})",
      R"({"action":"delay_reply","us":2000})",
      R"({"action":"corrupt_crc","match":{"address":[132,135]}})",
      R"({"action":"flip_bits","bits":3})",
      R"({"action":"truncate_reply","bytes":5})",
      R"({"action":"truncate_reply"})",
      R"({"action":"garbage_before","data":[1,2,255]})",
      R"({"action":"garbage_before","bytes":6})",
      R"({"action":"duplicate_reply","from_ms":10,"until_ms":20.5})",
      R"({"action":"wrong_id","id":7})",
      R"({"action":"wrong_id"})",
      R"({"action":"echo_instruction"})",
      R"({"action":"noise","bytes":3})",
      R"({"action":"corrupt_instruction","match":{"instruction":["write","sync_write"]}})",
      R"({"action":"hardware_error","kind":"overheating","match":{"port":"dxl0","servos":3}})",
      R"({"action":"silence","match":{"servos":[1,2]}})",
      R"({"action":"silence_until_reboot","count":1})",
      R"({"action":"slow","us":3000})",
      R"({"action":"eeprom_busy","us_per_byte":4000})",
      R"({"action":"eeprom_busy"})",
      R"({"action":"modbus_exception","match":{"instruction":"write_single_register"}})",
      R"({"action":"modbus_exception","code":2,"count":1})",
  };
  std::set<std::string> actions;
  for (const std::string& text : rules) {
    INFO(text);
    const faults::Rule rule = parse_rule(json::parse(text));
    const auto printed = faults::rule_json(rule);
    const faults::Rule again = parse_rule(json::parse(printed.dump()));
    CHECK(faults::rule_json(again) == printed);
    actions.insert(printed["action"].get<std::string>());
  }
  CHECK(actions.size() == faults::all_actions().size());
}

TEST_CASE("A rule reads its members into the right fields", "[faults]") {
  const faults::Rule r = parse_rule(json::parse(
      R"({"action":"drop_reply","match":{"port":"dxl0","servos":[3,4],"instruction":"read","address":132},"probability":0.25,"count":10,"after":100,"from_ms":1.5,"until_ms":20})"));
  CHECK(r.action == faults::Action::DropReply);
  CHECK(r.match.port == "dxl0");
  CHECK(r.match.servos == std::vector<std::uint8_t>{3, 4});
  CHECK(r.match.instructions == std::vector<std::string>{"read"});
  CHECK(r.match.address == std::pair<std::uint16_t, std::uint16_t>{132, 132});
  CHECK(r.trigger.probability == 0.25);
  CHECK(r.trigger.count == 10U);
  CHECK(r.trigger.after == 100U);
  CHECK(r.trigger.from == std::chrono::microseconds(1500));
  CHECK(r.trigger.until == std::chrono::milliseconds(20));
  const faults::Rule busy = parse_rule(json::parse(R"({"action":"eeprom_busy"})"));
  CHECK(busy.per_byte == std::chrono::microseconds(8500));  // ATmega8 EEPROM write time
  const faults::Rule noise = parse_rule(json::parse(R"({"action":"noise"})"));
  CHECK(noise.bytes == 8U);
}

TEST_CASE("A malformed rule is refused naming the member and the reason", "[faults]") {
  CHECK(refusal("[1]") == ": a rule must be a JSON object with at least \"action\"");
  CHECK(refusal("{}") == "/action: missing: say what the rule does (e.g. \"drop_reply\")");
  CHECK(refusal(R"({"action":"explode"})").rfind("/action: must be one of drop_reply, ", 0) == 0);
  CHECK(
      refusal(R"({"action":"drop_reply","us":5})").rfind("/us: unknown member for drop_reply", 0) ==
      0);
  CHECK(refusal(R"({"action":"drop_reply","match":{"servos":[300]}})") ==
        "/match/servos/0: must be an integer from 0 to 252, not 300");
  CHECK(refusal(R"({"action":"drop_reply","match":{"servos":[]}})") ==
        "/match/servos: must not be empty (leave it out to match everything)");
  CHECK(refusal(R"({"action":"drop_reply","match":{"instruction":"jump"}})")
            .rfind("/match/instruction: must be an instruction name: ping, read, ", 0) == 0);
  CHECK(refusal(R"({"action":"drop_reply","match":{"address":[10,2]}})") ==
        "/match/address: last address comes before the first");
  CHECK(refusal(R"({"action":"drop_reply","match":{"colour":"red"}})") ==
        "/match/colour: unknown member (match takes port, servos, instruction, address)");
  CHECK(refusal(R"({"action":"drop_reply","match":{"port":5}})") ==
        "/match/port: must be a port name (a string)");
  CHECK(refusal(R"({"action":"drop_reply","probability":1.5})") ==
        "/probability: must be a number from 0 to 1, not 1.5");
  CHECK(refusal(R"({"action":"drop_reply","count":0})")
            .rfind("/count: must be an integer from 1 to ", 0) == 0);
  CHECK(refusal(R"({"action":"drop_reply","after":-1})")
            .rfind("/after: must be an integer from 0 to ", 0) == 0);
  CHECK(refusal(R"({"action":"drop_reply","from_ms":20,"until_ms":10})") ==
        "/until_ms: must be later than from_ms");
  CHECK(refusal(R"({"action":"delay_reply"})") == "/us: missing: how many microseconds to add");
  CHECK(refusal(R"({"action":"slow","us":20000000})") ==
        "/us: must be an integer from 0 to 10000000, not 20000000");
  CHECK(
      refusal(R"({"action":"hardware_error"})").rfind("/kind: missing: which hardware error", 0) ==
      0);
  CHECK(refusal(R"({"action":"hardware_error","kind":"melting"})") ==
        "/kind: must be one of overheating, overload, input_voltage, electrical_shock, encoder, "
        "hall_sensor");
  CHECK(refusal(R"({"action":"hardware_error","kind":"overload","probability":0.5})")
            .rfind("/probability: hardware_error is a state of the servo", 0) == 0);
  CHECK(
      refusal(R"({"action":"hardware_error","kind":"overload","match":{"instruction":"read"}})") ==
      "/match: hardware_error matches servos only (port and servos)");
  CHECK(refusal(R"({"action":"garbage_before","bytes":2,"data":[1]})") ==
        "/bytes: give either data or bytes, not both");
  CHECK(refusal(R"({"action":"garbage_before","data":[256]})") ==
        "/data/0: must be an integer from 0 to 255, not 256");
  CHECK(refusal(R"({"action":"flip_bits","bits":0})") ==
        "/bits: must be an integer from 1 to 64, not 0");
  CHECK(refusal(R"({"action":"wrong_id","id":254})") ==
        "/id: must be an integer from 0 to 253, not 254");
}
