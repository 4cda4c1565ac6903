// FEETECH instruction layouts are validated like Protocol 1.0's and say which rule failed; codes
// FEETECH does not define decode as unknown; the encoder refuses what FEETECH cannot express.
#include <catch2/catch.hpp>

#include "wire/describe.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"
#include "wire/protocol.hpp"
#include "wire/status_error.hpp"

using namespace dxlemu;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

constexpr auto kFt = Protocol::Feetech;

wire::Frame frame(Protocol protocol, std::uint8_t instruction, Bytes params) {
  wire::Frame f;
  f.protocol = protocol;
  f.id = 1;
  f.instruction = instruction;
  f.params = std::move(params);
  f.raw = wire::encode_packet(protocol, f.id, instruction, f.params);
  return f;
}

// "error <kind>: <reason>", or the description of what decoded.
std::string outcome(Protocol protocol, std::uint8_t instruction, Bytes params) {
  const auto result = wire::decode_instruction(frame(protocol, instruction, std::move(params)));
  if (const auto* e = std::get_if<wire::DecodeError>(&result)) {
    const char* kind = e->kind == wire::DecodeErrorKind::BadLength ? "bad_length" : "bad_value";
    return std::string("error ") + kind + ": " + e->reason;
  }
  return wire::describe(std::get<wire::InstructionPacket>(result));
}

std::string outcome(std::uint8_t instruction, Bytes params) {
  return outcome(kFt, instruction, std::move(params));
}

std::string encode_error(const wire::InstructionPacket& packet) {
  try {
    wire::encode_instruction(packet);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "encoded";
}

}  // namespace

TEST_CASE("FEETECH instructions without parameters refuse any", "[wire][feetech][decode]") {
  CHECK(outcome(0x01, {0x00}) ==
        "error bad_length: ping needs no parameters, got 1 parameter bytes");
  CHECK(outcome(0x05, {0x01}) ==
        "error bad_length: action needs no parameters, got 1 parameter bytes");
  CHECK(outcome(0x06, {0xFF}) ==
        "error bad_length: parameter_recovery needs no parameters, got 1 parameter bytes");
  CHECK(outcome(0x08, {0x01, 0x02}) ==
        "error bad_length: reboot needs no parameters, got 2 parameter bytes");
  CHECK(outcome(0x09, {0x01}) ==
        "error bad_length: parameter_backup needs no parameters, got 1 parameter bytes");
  CHECK(outcome(0x0A, {0x01}) ==
        "error bad_length: status_reset needs no parameters, got 1 parameter bytes");
}

TEST_CASE("FEETECH Read takes a one-byte address and length", "[wire][feetech][decode]") {
  CHECK(outcome(0x02, {0x38, 0x02}) == "id=1 read address=56 length=2");
  CHECK(outcome(0x02, {0x38}) ==
        "error bad_length: read needs 2 bytes (address, length), got 1 parameter bytes");
  CHECK(outcome(0x02, {0x38, 0x00, 0x02}) ==
        "error bad_length: read needs 2 bytes (address, length), got 3 parameter bytes");
  CHECK(outcome(0x02, {0x38, 0x00}) == "error bad_value: read data length must be at least 1");
  CHECK(outcome(0x02, {0xFF, 0xFF}) == "id=1 read address=255 length=255");
}

TEST_CASE("FEETECH Write and Reg Write need an address and data", "[wire][feetech][decode]") {
  CHECK(outcome(0x03, {0x28, 0x01}) == "id=1 write address=40 data=01");
  CHECK(outcome(0x03, {0x28}) ==
        "error bad_length: write needs an address and at least 1 data byte, got 1 parameter bytes");
  CHECK(outcome(0x03, {}) ==
        "error bad_length: write needs an address and at least 1 data byte, got 0 parameter bytes");
  CHECK(outcome(0x04, {0x2A}) ==
        "error bad_length: reg_write needs an address and at least 1 "
        "data byte, got 1 parameter bytes");
  CHECK(outcome(0x04, {0x2A, 0x00, 0x08}) == "id=1 reg_write address=42 data=00 08");
}

TEST_CASE("FEETECH Position calibration takes nothing or a 16-bit position",
          "[wire][feetech][decode]") {
  CHECK(outcome(0x0B, {}) == "id=1 position_calibration");
  CHECK(outcome(0x0B, {0xFF, 0x0F}) == "id=1 position_calibration position=4095");
  CHECK(outcome(0x0B, {0x00}) ==
        "error bad_length: position_calibration needs no parameters or 2 "
        "bytes (position, low byte first), got 1 parameter bytes");
  CHECK(outcome(0x0B, {0x00, 0x04, 0x00}) ==
        "error bad_length: position_calibration needs no parameters or 2 bytes (position, low "
        "byte first), got 3 parameter bytes");
}

TEST_CASE("FEETECH Sync Read takes a one-byte address and length and at least one ID",
          "[wire][feetech][decode]") {
  CHECK(outcome(0x82, {0x38, 0x02, 0x01}) == "id=1 sync_read address=56 length=2 ids=1");
  CHECK(outcome(0x82, {0x38, 0x02}) ==
        "error bad_length: sync_read needs 2 bytes (address, "
        "length) and at least one ID, got 2 parameter bytes");
  CHECK(outcome(0x82, {}) ==
        "error bad_length: sync_read needs 2 bytes (address, length) and at "
        "least one ID, got 0 parameter bytes");
  CHECK(outcome(0x82, {0x38, 0x00, 0x01}) ==
        "error bad_value: sync_read data length must be at least 1");
  // The 2.0 layout (two-byte address and length) reads as address 56, length 0: refused.
  CHECK(outcome(0x82, {0x38, 0x00, 0x02, 0x00, 0x01}) ==
        "error bad_value: sync_read data length must be at least 1");
}

TEST_CASE("FEETECH Sync Write blocks must divide the parameters evenly",
          "[wire][feetech][decode]") {
  CHECK(outcome(0x83, {0x2A, 0x02, 0x01, 0x00, 0x08, 0x02, 0xFF, 0x07}) ==
        "id=1 sync_write address=42 length=2 [1: 00 08] [2: FF 07]");
  CHECK(outcome(0x83, {0x2A, 0x02, 0x01, 0x00}) ==
        "error bad_length: sync_write blocks of 3 bytes (ID + 2 bytes) must divide the remaining "
        "2 bytes");
  CHECK(outcome(0x83, {0x2A, 0x02}) ==
        "error bad_length: sync_write blocks of 3 bytes (ID + 2 "
        "bytes) must divide the remaining 0 bytes");
  CHECK(outcome(0x83, {0x2A}) ==
        "error bad_length: sync_write needs 2 bytes (address, length) and "
        "data blocks, got 1 parameter bytes");
  CHECK(outcome(0x83, {0x2A, 0x00, 0x01}) ==
        "error bad_value: sync_write data length must be at least 1");
}

TEST_CASE(
    "Codes FEETECH does not define decode as unknown, and FEETECH's own are unknown to "
    "DYNAMIXEL",
    "[wire][feetech][decode]") {
  // DYNAMIXEL-only codes (Clear, Backup, Status, the Fast and Bulk instructions) and free codes.
  for (const std::uint8_t code : {0x00, 0x07, 0x0C, 0x10, 0x20, 0x55, 0x8A, 0x92, 0x93, 0x9A}) {
    INFO("code " << int{code});
    CHECK(outcome(code, {0x01}).rfind("id=1 unknown instruction=", 0) == 0);
  }
  CHECK(outcome(0x92, {0x00, 0x02, 0x01, 0x1E}) ==
        "id=1 unknown instruction=0x92 params=00 02 01 1E");
  for (const Protocol dxl : {Protocol::V1, Protocol::V2}) {
    for (const std::uint8_t code : {0x09, 0x0A, 0x0B}) {
      INFO("code " << int{code});
      CHECK(outcome(dxl, code, {}).rfind("id=1 unknown instruction=", 0) == 0);
    }
  }
}

TEST_CASE("FEETECH instructions re-encode, and what FEETECH cannot express is refused",
          "[wire][feetech][encode]") {
  CHECK(wire::encode_instruction({kFt, 1, wire::PositionCalibration{1024}}) ==
        Bytes{0xFF, 0xFF, 0x01, 0x04, 0x0B, 0x00, 0x04, 0xEB});
  CHECK(wire::encode_instruction({kFt, 0xFE, wire::SyncRead{0x38, 8, {1, 2}}}) ==
        Bytes{0xFF, 0xFF, 0xFE, 0x06, 0x82, 0x38, 0x08, 0x01, 0x02, 0x36});
  CHECK(encode_error({kFt, 1, wire::Read{256, 2}}) == "FEETECH address 256 does not fit one byte");
  CHECK(encode_error({kFt, 1, wire::FactoryReset{}}) == "factory_reset does not exist in FEETECH");
  CHECK(encode_error({kFt, 0xFE, wire::BulkRead{{{1, 0x38, 2}}}}) ==
        "bulk_read does not exist in FEETECH");
  CHECK(encode_error({kFt, 1, wire::Clear{0x01, {0x44, 0x58, 0x4C, 0x22}}}) ==
        "clear does not exist in FEETECH");
  CHECK(encode_error({kFt, 0xFE, wire::FastSyncRead{}}) ==
        "fast_sync_read does not exist in FEETECH");
  CHECK(encode_error({kFt, 0xFE, wire::BulkWrite{}}) == "bulk_write does not exist in FEETECH");
  CHECK(encode_error({Protocol::V1, 1, wire::StatusReset{}}) ==
        "status_reset does not exist in Protocol 1.0");
  CHECK(encode_error({Protocol::V2, 1, wire::ParameterBackup{}}) ==
        "parameter_backup does not exist in Protocol 2.0");
  CHECK(encode_error({Protocol::V2, 1, wire::ParameterRecovery{}}) ==
        "parameter_recovery does not exist in Protocol 2.0");
  CHECK(encode_error({Protocol::V1, 1, wire::PositionCalibration{}}) ==
        "position_calibration does not exist in Protocol 1.0");
  CHECK(encode_error({Protocol::V1, 0xFE, wire::SyncRead{0x24, 2, {1}}}) ==
        "sync_read does not exist in Protocol 1.0");
  // LENGTH is one byte: 253 parameter bytes fit, 254 do not.
  CHECK(wire::encode_instruction({kFt, 1, wire::Write{0x00, Bytes(252, 0x11)}}).size() == 259);
  CHECK(encode_error({kFt, 1, wire::Write{0x00, Bytes(253, 0x11)}}) ==
        "FEETECH LENGTH 256 does not fit one byte");
}

TEST_CASE("FEETECH status packets carry the servo status bits in the error position",
          "[wire][feetech][status]") {
  // FTServo_Python ERRBIT_*: 1 voltage, 2 angle sensor, 4 overheat, 8 current, 32 overload.
  CHECK(wire::feetech_error::kVoltage == 1);
  CHECK(wire::feetech_error::kAngleSensor == 2);
  CHECK(wire::feetech_error::kOverheat == 4);
  CHECK(wire::feetech_error::kOverCurrent == 8);
  CHECK(wire::feetech_error::kOverload == 32);
  CHECK(wire::feetech_error::kDefinedBits == 0x2F);
  const std::uint8_t error = wire::feetech_error::kOverheat | wire::feetech_error::kOverload;
  const Bytes bytes = wire::encode_status({kFt, 3, error, {0x18, 0x05}});
  CHECK(bytes == Bytes{0xFF, 0xFF, 0x03, 0x04, 0x24, 0x18, 0x05, 0xB7});
  const auto status = wire::decode_status(frame(kFt, error, {0x18, 0x05}));
  REQUIRE(std::holds_alternative<wire::StatusPacket>(status));
  CHECK(wire::describe(std::get<wire::StatusPacket>(status)) == "id=1 error=0x24 params=18 05");
}

TEST_CASE("Protocol and FEETECH instruction names", "[wire][feetech]") {
  CHECK(wire::protocol_name(Protocol::V1) == "1.0");
  CHECK(wire::protocol_name(Protocol::V2) == "2.0");
  CHECK(wire::protocol_name(kFt) == "feetech");
  CHECK(static_cast<int>(kFt) == 0x46);
  CHECK(wire::instruction_name(kFt, 0x06) == "parameter_recovery");
  CHECK(wire::instruction_name(Protocol::V1, 0x06) == "factory_reset");
  CHECK(wire::instruction_name(kFt, 0x08) == "reboot");
  CHECK(wire::instruction_name(kFt, 0x09) == "parameter_backup");
  CHECK(wire::instruction_name(kFt, 0x0A) == "status_reset");
  CHECK(wire::instruction_name(kFt, 0x0B) == "position_calibration");
  CHECK(wire::instruction_name(kFt, 0x82) == "sync_read");
  CHECK(wire::instruction_name(kFt, 0x92) == "unknown");
  CHECK(wire::max_unicast_id(kFt) == 253);
  CHECK(wire::is_valid_packet_id(kFt, 0xFD));
  CHECK(wire::is_valid_packet_id(kFt, 0xFE));
  CHECK_FALSE(wire::is_valid_packet_id(kFt, 0xFF));
}
