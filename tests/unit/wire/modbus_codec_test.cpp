// Modbus RTU's codec: CRC, requests as control-table reads and writes, responses, exceptions,
// against the frames computed in modbus-rtu.md.
#include <catch2/catch.hpp>

#include <string_view>

#include "wire/crc16_modbus.hpp"
#include "wire/hex.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::test::modbus_codec {

using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

Bytes hex(std::string_view text) {
  return wire::parse_hex(text).value();
}

wire::Frame frame_of(const Bytes& raw) {
  wire::Frame f;
  f.protocol = Protocol::Modbus;
  f.id = raw[0];
  f.instruction = raw[1];
  f.params.assign(raw.begin() + 2, raw.end() - 2);
  f.raw = raw;
  return f;
}

wire::Instruction decoded(const Bytes& raw) {
  const auto result = wire::decode_modbus_request(frame_of(raw));
  REQUIRE(std::holds_alternative<wire::InstructionPacket>(result));
  return std::get<wire::InstructionPacket>(result).instruction;
}

wire::DecodeError refused(const Bytes& raw) {
  const auto result = wire::decode_modbus_request(frame_of(raw));
  REQUIRE(std::holds_alternative<wire::DecodeError>(result));
  return std::get<wire::DecodeError>(result);
}

TEST_CASE("CRC-16/MODBUS has the check value 0x4B37", "[wire][modbus]") {
  const std::string_view text = "123456789";
  const Bytes bytes(text.begin(), text.end());
  CHECK(wire::crc16_modbus(bytes) == 0x4B37);
}

TEST_CASE("Modbus requests are built with the reference note's CRCs", "[wire][modbus]") {
  CHECK(wire::encode_modbus_frame(1, 0x03, hex("00 00 00 0A")) == hex("01 03 00 00 00 0A C5 CD"));
  CHECK(wire::encode_modbus_frame(0x11, 0x03, hex("00 6B 00 03")) ==
        hex("11 03 00 6B 00 03 76 87"));
  CHECK(wire::encode_instruction({Protocol::Modbus, 1, wire::Read{0, 4}}) ==
        hex("01 03 00 00 00 02 C4 0B"));
  CHECK(wire::encode_instruction({Protocol::Modbus, 1, wire::Read{564, 4}}) ==
        hex("01 03 01 1A 00 02 E4 30"));
  CHECK(wire::encode_instruction({Protocol::Modbus, 1, wire::Write{512, {0x01, 0x00}}}) ==
        hex("01 06 01 00 00 01 49 F6"));
  CHECK(wire::encode_instruction({Protocol::Modbus, 1, wire::Write{564, {0x00, 0x08, 0, 0}}}) ==
        hex("01 10 01 1A 00 02 04 08 00 00 00 7D 2C"));
}

TEST_CASE("Register requests decode as reads and writes of control-table bytes", "[wire][modbus]") {
  // Goal Position (564) = 40283-40284, PDU 0x011A: two registers, low word first.
  CHECK(decoded(hex("01 03 01 1A 00 02 E4 30")) == wire::Instruction{wire::Read{564, 4}});
  CHECK(decoded(wire::encode_modbus_frame(1, 0x04, hex("01 22 00 02"))) ==
        wire::Instruction{wire::Read{580, 4}});
  // Torque Enable (512) low byte, LED Red (513) high byte of 40257.
  CHECK(decoded(hex("01 06 01 00 00 01 49 F6")) ==
        wire::Instruction{wire::Write{512, {0x01, 0x00}}});
  // Goal Position = 2048: registers 0x0800, 0x0000 are table bytes 00 08 00 00.
  CHECK(decoded(hex("01 10 01 1A 00 02 04 08 00 00 00 7D 2C")) ==
        wire::Instruction{wire::Write{564, {0x00, 0x08, 0x00, 0x00}}});
  CHECK(decoded(wire::encode_modbus_frame(1, 0x17, hex("01 22 00 02 01 1A 00 01 02 12 34"))) ==
        wire::Instruction{wire::WriteRead{{564, {0x34, 0x12}}, {580, 4}}});
  CHECK(decoded(wire::encode_modbus_frame(1, 0x08, hex("00 00 A5 37"))) ==
        wire::Instruction{wire::Echo{{0xA5, 0x37}}});
}

TEST_CASE("Modbus refusals follow the spec's order: function, quantity, address",
          "[wire][modbus]") {
  // Function codes it does not serve, and Diagnostics sub-functions other than 0000.
  CHECK(std::holds_alternative<wire::UnknownInstruction>(
      decoded(wire::encode_modbus_frame(1, 0x01, hex("00 00 00 01")))));
  CHECK(std::holds_alternative<wire::UnknownInstruction>(
      decoded(wire::encode_modbus_frame(1, 0x08, hex("00 01 00 00")))));
  // Quantity 0 or over 125 (03), checked before the address (02).
  CHECK(refused(wire::encode_modbus_frame(1, 0x03, hex("FF FF 00 00"))).kind ==
        wire::DecodeErrorKind::BadValue);
  CHECK(refused(wire::encode_modbus_frame(1, 0x03, hex("00 00 00 7E"))).kind ==
        wire::DecodeErrorKind::BadValue);
  CHECK(refused(wire::encode_modbus_frame(1, 0x10, hex("00 00 00 7C F8"))).kind ==
        wire::DecodeErrorKind::BadValue);
  // Byte count not twice the quantity.
  CHECK(refused(wire::encode_modbus_frame(1, 0x10, hex("01 1A 00 02 03 08 00 00"))).kind ==
        wire::DecodeErrorKind::BadValue);
  // Values that do not fill the byte count, and fields of the wrong size.
  CHECK(refused(wire::encode_modbus_frame(1, 0x10, hex("01 1A 00 02 04 08 00"))).kind ==
        wire::DecodeErrorKind::BadLength);
  CHECK(refused(wire::encode_modbus_frame(1, 0x03, hex("00 00 00"))).kind ==
        wire::DecodeErrorKind::BadLength);
  CHECK(refused(wire::encode_modbus_frame(1, 0x06, hex("01 00 00 01 00"))).kind ==
        wire::DecodeErrorKind::BadLength);
  // Registers whose bytes lie past 16-bit addresses.
  CHECK(refused(wire::encode_modbus_frame(1, 0x03, hex("7F FF 00 02"))).kind ==
        wire::DecodeErrorKind::BadAddress);
  CHECK(refused(wire::encode_modbus_frame(1, 0x06, hex("80 00 00 01"))).kind ==
        wire::DecodeErrorKind::BadAddress);
}

TEST_CASE("Modbus responses: registers big-endian, write echoes, exceptions", "[wire][modbus]") {
  // The spec's example: server 17, registers 0x022B, 0x0000, 0x0064.
  const wire::Instruction read3 = wire::Read{216, 6};
  CHECK(wire::encode_modbus_response(0x11, 0x03, &read3, 0, hex("2B 02 00 00 64 00")) ==
        hex("11 03 06 02 2B 00 00 00 64 C8 BA"));
  const wire::Instruction single = wire::Write{512, {0x01, 0x00}};
  CHECK(wire::encode_modbus_response(1, 0x06, &single, 0, {}) == hex("01 06 01 00 00 01 49 F6"));
  const wire::Instruction multiple = wire::Write{564, {0x00, 0x08, 0x00, 0x00}};
  CHECK(wire::encode_modbus_response(1, 0x10, &multiple, 0, {}) ==
        wire::encode_modbus_frame(1, 0x10, hex("01 1A 00 02")));
  const wire::Instruction echo = wire::Echo{{0xA5, 0x37}};
  CHECK(wire::encode_modbus_response(1, 0x08, &echo, 0, {}) ==
        wire::encode_modbus_frame(1, 0x08, hex("00 00 A5 37")));
  CHECK(wire::encode_modbus_response(1, 0x03, &read3, 0x02, {}) == hex("01 83 02 C0 F1"));
  // The status vocabulary of the row gives the exception codes.
  const wire::DeviceFaults none;
  CHECK(wire::status_error_byte(Protocol::Modbus, wire::Outcome::Access, none) == 0x02);
  CHECK(wire::status_error_byte(Protocol::Modbus, wire::Outcome::DataRange, none) == 0x03);
  CHECK(wire::status_error_byte(Protocol::Modbus, wire::Outcome::Locked, none) == 0x04);
  CHECK(wire::status_error_byte(Protocol::Modbus, wire::Outcome::UnknownInstruction, none) == 0x01);
  CHECK(wire::encode_reply({Protocol::Modbus, 1, 0x02, {}}, {0x03, &read3}) ==
        hex("01 83 02 C0 F1"));
}

}  // namespace dxlemu::test::modbus_codec
