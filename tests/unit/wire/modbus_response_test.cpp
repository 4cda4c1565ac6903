// A master's side of Modbus RTU: responses decoded into registers as control-table bytes,
// exception codes, and frames that are no response (dxlemu clone reads servos with them).
#include <catch2/catch.hpp>

#include <string_view>

#include "wire/hex.hpp"
#include "wire/modbus_codec.hpp"

namespace dxlemu::test::modbus_response {

using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

Bytes hex(std::string_view text) {
  return wire::parse_hex(text).value();
}

wire::DecodeResult<wire::ModbusResponse> decode(const Bytes& raw) {
  wire::Frame f;
  f.protocol = Protocol::Modbus;
  f.id = raw[0];
  f.instruction = raw[1];
  f.params.assign(raw.begin() + 2, raw.end() - 2);
  f.raw = raw;
  return wire::decode_modbus_response(f);
}

wire::ModbusResponse response(const Bytes& raw) {
  auto result = decode(raw);
  REQUIRE(std::holds_alternative<wire::ModbusResponse>(result));
  return std::get<wire::ModbusResponse>(result);
}

TEST_CASE("A read's response gives its registers as control-table bytes, low byte first",
          "[wire][modbus]") {
  // The spec's example: server 17, registers 0x022B, 0x0000, 0x0064.
  CHECK(response(hex("11 03 06 02 2B 00 00 00 64 C8 BA")) ==
        wire::ModbusResponse{0x11, 0x03, 0, hex("2B 02 00 00 64 00")});
  // Function 04 and 23 read the same way.
  CHECK(response(wire::encode_modbus_frame(1, 0x04, hex("02 07 E4"))).data == hex("E4 07"));
  CHECK(response(wire::encode_modbus_frame(1, 0x17, hex("04 00 01 00 02"))).data ==
        hex("01 00 02 00"));
  CHECK(wire::registers_read(hex("04 07 E4 00 00")) == hex("E4 07 00 00"));
}

TEST_CASE("Write and Diagnostics responses come as they are, and exceptions carry their code",
          "[wire][modbus]") {
  CHECK(response(hex("01 06 01 00 00 01 49 F6")) ==
        wire::ModbusResponse{1, 0x06, 0, hex("01 00 00 01")});
  CHECK(response(wire::encode_modbus_frame(1, 0x10, hex("01 1A 00 02"))).data ==
        hex("01 1A 00 02"));
  CHECK(response(wire::encode_modbus_frame(1, 0x08, hex("00 00 A5 37"))).data ==
        hex("00 00 A5 37"));
  CHECK(response(hex("01 83 02 C0 F1")) == wire::ModbusResponse{1, 0x03, 0x02, {}});
  CHECK(response(wire::encode_modbus_frame(7, 0x90, hex("06"))) ==
        wire::ModbusResponse{7, 0x10, 0x06, {}});
}

TEST_CASE("Frames that are no response of their function are NotStatus", "[wire][modbus]") {
  for (const Bytes& raw : {
           wire::encode_modbus_frame(1, 0x03, hex("04 07 E4 00")),  // byte count 4, 3 bytes
           wire::encode_modbus_frame(1, 0x03, hex("03 07 E4 00")),  // half a register
           wire::encode_modbus_frame(1, 0x03, {}),                  // no byte count
           wire::encode_modbus_frame(1, 0x83, hex("02 00")),        // exception of 2 bytes
           wire::encode_modbus_frame(1, 0x83, {}),                  // exception without code
           wire::encode_modbus_frame(1, 0x01, hex("01 00")),        // Read Coils: not served
       }) {
    INFO(wire::to_hex(raw));
    const auto result = decode(raw);
    REQUIRE(std::holds_alternative<wire::DecodeError>(result));
    CHECK(std::get<wire::DecodeError>(result).kind == wire::DecodeErrorKind::NotStatus);
  }
  CHECK(!wire::registers_read(hex("02 07")));
}

}  // namespace dxlemu::test::modbus_response
