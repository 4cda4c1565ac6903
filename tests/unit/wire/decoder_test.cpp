// Decoding validates every parameter layout and says which rule failed; it never throws.
#include <catch2/catch.hpp>

#include "wire/describe.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using wire::Protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

wire::Frame frame(Protocol protocol, std::uint8_t id, std::uint8_t instruction, Bytes params) {
  wire::Frame f;
  f.protocol = protocol;
  f.id = id;
  f.instruction = instruction;
  f.params = std::move(params);
  f.raw = wire::encode_packet(protocol, id, instruction, f.params);
  return f;
}

std::string error_of(Protocol protocol, std::uint8_t instruction, Bytes params) {
  const auto result = wire::decode_instruction(frame(protocol, 1, instruction, std::move(params)));
  if (const auto* e = std::get_if<wire::DecodeError>(&result)) {
    return e->reason;
  }
  return "decoded: " + wire::describe(std::get<wire::InstructionPacket>(result));
}

std::string decoded(Protocol protocol, std::uint8_t instruction, Bytes params) {
  const auto result = wire::decode_instruction(frame(protocol, 1, instruction, std::move(params)));
  if (const auto* e = std::get_if<wire::DecodeError>(&result)) {
    return "error: " + e->reason;
  }
  return wire::describe(std::get<wire::InstructionPacket>(result));
}

constexpr auto kV1 = Protocol::V1;
constexpr auto kV2 = Protocol::V2;

}  // namespace

TEST_CASE("Parameter counts are checked for every fixed-layout instruction", "[wire][decode]") {
  CHECK(error_of(kV2, 0x01, {0x00}) == "ping needs no parameters, got 1 parameter bytes");
  CHECK(error_of(kV2, 0x02, {0x84, 0x00, 0x04}) ==
        "read needs 4 bytes (address, length), got 3 parameter bytes");
  CHECK(error_of(kV1, 0x02, {0x2B, 0x01, 0x00}) ==
        "read needs 2 bytes (address, length), got 3 parameter bytes");
  CHECK(error_of(kV2, 0x03, {0x74, 0x00}) ==
        "write needs an address and at least 1 data byte, got 2 parameter bytes");
  CHECK(error_of(kV2, 0x05, {0x01}) == "action needs no parameters, got 1 parameter bytes");
  CHECK(error_of(kV2, 0x08, {0x01}) == "reboot needs no parameters, got 1 parameter bytes");
  CHECK(error_of(kV2, 0x06, {}) == "factory_reset needs 1 byte (option), got 0 parameter bytes");
  CHECK(error_of(kV1, 0x06, {0x01}) == "factory_reset needs no parameters, got 1 parameter bytes");
}

TEST_CASE("A read or sync read of zero bytes is refused", "[wire][decode]") {
  CHECK(error_of(kV2, 0x02, {0x84, 0x00, 0x00, 0x00}) == "read data length must be at least 1");
  CHECK(error_of(kV2, 0x82, {0x84, 0x00, 0x00, 0x00, 0x01}) ==
        "sync_read data length must be at least 1");
}

TEST_CASE("Sync Write blocks must divide the parameters evenly", "[wire][decode]") {
  // address 116, length 4, then ID 1 + 4 bytes and a stray byte.
  CHECK(error_of(kV2, 0x83, {0x74, 0x00, 0x04, 0x00, 0x01, 0x96, 0x00, 0x00, 0x00, 0x02}) ==
        "sync_write blocks of 5 bytes (ID + 4 bytes) must divide the remaining 6 bytes");
  CHECK(error_of(kV2, 0x83, {0x74, 0x00, 0x04, 0x00}) ==
        "sync_write blocks of 5 bytes (ID + 4 bytes) must divide the remaining 0 bytes");
  CHECK(error_of(kV1, 0x83, {0x1E, 0x02, 0x00, 0x10}) ==
        "sync_write blocks of 3 bytes (ID + 2 bytes) must divide the remaining 2 bytes");
  CHECK(decoded(kV1, 0x83, {0x1E, 0x02, 0x00, 0x10, 0x00, 0x01, 0x20, 0x02}) ==
        "id=1 sync_write address=30 length=2 [0: 10 00] [1: 20 02]");
}

TEST_CASE("Bulk Read layouts differ between the protocols and are both validated",
          "[wire][decode]") {
  CHECK(decoded(kV1, 0x92, {0x00, 0x02, 0x01, 0x1E}) == "id=1 bulk_read [1: address=30 length=2]");
  CHECK(error_of(kV1, 0x92, {0x01, 0x02, 0x01, 0x1E}) == "bulk_read first parameter must be 0x00");
  CHECK(error_of(kV1, 0x92, {0x00, 0x02, 0x01}) ==
        "bulk_read needs 0x00 and blocks of 3 bytes (length, ID, address), got 3 parameter bytes");
  CHECK(error_of(kV2, 0x92, {0x01, 0x90, 0x00, 0x02}) ==
        "bulk_read needs blocks of 5 bytes (ID, address, length), got 4 parameter bytes");
  CHECK(error_of(kV2, 0x9A, {0x01, 0x90, 0x00, 0x00, 0x00}) ==
        "fast_bulk_read data length must be at least 1");
}

TEST_CASE("Bulk Write blocks must hold the data they announce", "[wire][decode]") {
  CHECK(error_of(kV2, 0x93, {0x01, 0x20, 0x00, 0x02, 0x00, 0xA0}) ==
        "bulk_write block 1 announces 2 bytes of data, 1 byte left");
  CHECK(error_of(kV2, 0x93, {0x01, 0x20, 0x00, 0x01, 0x00, 0xA0, 0x02, 0x1F}) ==
        "bulk_write block 2 is cut short: 2 bytes left");
  CHECK(decoded(kV2, 0x93, {0x01, 0x20, 0x00, 0x01, 0x00, 0xA0}) ==
        "id=1 bulk_write [1: address=32 data=A0]");
}

TEST_CASE("Factory Reset, Clear and Backup options are checked", "[wire][decode]") {
  CHECK(error_of(kV2, 0x06, {0x03}) == "factory_reset option must be 0xFF, 0x01 or 0x02, got 0x03");
  CHECK(error_of(kV2, 0x10, {0x01, 0x44, 0x58, 0x4C}) ==
        "clear option 0x01 needs the fixed bytes 44 58 4C 22, got 44 58 4C");
  CHECK(error_of(kV2, 0x10, {0x01}) ==
        "clear option 0x01 needs the fixed bytes 44 58 4C 22, got none");
  CHECK(error_of(kV2, 0x20, {0x02, 0x43, 0x54, 0x52, 0x4D}) ==
        "control_table_backup option 0x02 needs the fixed bytes 43 54 52 4C, got 43 54 52 4D");
  // Reserved options are passed on for the servo to refuse.
  CHECK(decoded(kV2, 0x10, {0x02}) == "id=1 clear option=0x02");
  CHECK(decoded(kV2, 0x20, {0x03, 0x09}) == "id=1 control_table_backup option=0x03 data=09");
}

TEST_CASE("Undefined instructions decode as unknown so that a servo can answer Instruction Error",
          "[wire][decode]") {
  CHECK(decoded(kV2, 0x77, {0x01, 0x02}) == "id=1 unknown instruction=0x77 params=01 02");
  CHECK(decoded(kV2, 0x55, {}) == "id=1 unknown instruction=0x55");
  // 2.0-only instructions do not exist in Protocol 1.0.
  for (const std::uint8_t code : {0x10, 0x20, 0x82, 0x8A, 0x93, 0x9A}) {
    CHECK(decoded(kV1, code, {0x01}).rfind("id=1 unknown instruction=", 0) == 0);
  }
}

TEST_CASE("Decode errors carry the unverified ID and instruction", "[wire][decode]") {
  const auto result = wire::decode_instruction(frame(kV2, 42, 0x02, {0x01}));
  REQUIRE(std::holds_alternative<wire::DecodeError>(result));
  const auto& e = std::get<wire::DecodeError>(result);
  CHECK(e.id == 42);
  CHECK(e.instruction == 0x02);
  CHECK(e.kind == wire::DecodeErrorKind::BadLength);
}

TEST_CASE("Only 0x55 packets with an error byte decode as 2.0 status", "[wire][decode]") {
  const auto not_status = wire::decode_status(frame(kV2, 1, 0x02, {0x00}));
  REQUIRE(std::holds_alternative<wire::DecodeError>(not_status));
  CHECK(std::get<wire::DecodeError>(not_status).kind == wire::DecodeErrorKind::NotStatus);
  CHECK(std::holds_alternative<wire::DecodeError>(wire::decode_status(frame(kV2, 1, 0x55, {}))));
}

TEST_CASE("A Fast reply must match the requested block lengths", "[wire][decode]") {
  const auto bytes = wire::encode_fast_reply({{{0x00, 1, {0x01, 0x02}}}});
  wire::Frame f = frame(kV2, 0xFE, 0x55, Bytes(bytes.begin() + 8, bytes.end() - 2));
  f.raw = bytes;
  const std::vector<std::uint16_t> wrong = {3};
  const auto result = wire::decode_fast_reply(f, wrong);
  REQUIRE(std::holds_alternative<wire::DecodeError>(result));
  CHECK(std::get<wire::DecodeError>(result).reason ==
        "fast reply needs 7 bytes for 1 blocks, got 6");
}

TEST_CASE("Encoding refuses what the protocol cannot express", "[wire][encode]") {
  CHECK_THROWS_AS(wire::encode_instruction({kV1, 1, wire::Read{300, 1}}), std::invalid_argument);
  CHECK_THROWS_AS(wire::encode_instruction({kV1, 1, wire::SyncRead{132, 4, {1}}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(wire::encode_instruction({kV1, 1, wire::FactoryReset{0x01}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(wire::encode_instruction({kV2, 0xFE, wire::SyncWrite{116, 4, {{1, {0x00}}}}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(wire::encode_packet(kV1, 1, 0x03, Bytes(254, 0x00)), std::invalid_argument);
}

TEST_CASE("Every instruction round-trips through encode and decode in both protocols",
          "[wire][decode]") {
  const std::vector<wire::Instruction> both = {
      wire::Ping{},
      wire::Read{43, 1},
      wire::Write{30, {0xF4, 0x01}},
      wire::RegWrite{30, {0xF4}},
      wire::Action{},
      wire::FactoryReset{},
      wire::Reboot{},
      wire::SyncWrite{30, 2, {{1, {0x01, 0x02}}, {2, {0x03, 0x04}}}},
      wire::BulkRead{{{1, 30, 2}, {2, 36, 2}}},
      wire::UnknownInstruction{0x7E, {0x01}},
  };
  const std::vector<wire::Instruction> v2_only = {
      wire::Clear{0x01, {0x44, 0x58, 0x4C, 0x22}},
      wire::ControlTableBackup{0x02, {0x43, 0x54, 0x52, 0x4C}},
      wire::SyncRead{600, 4, {1, 2, 3}},
      wire::FastSyncRead{{132, 4, {3, 7, 4}}},
      wire::FastBulkRead{{{{3, 132, 4}, {7, 124, 2}}}},
      wire::BulkWrite{{{1, 32, {0xA0, 0x00}}, {2, 31, {0x50}}}},
      wire::FactoryReset{wire::factory_reset::kResetAllButIdAndBaud},
  };
  auto round_trip = [](Protocol protocol, const wire::Instruction& instruction) {
    const wire::InstructionPacket packet{protocol, 7, instruction};
    const Bytes bytes = wire::encode_instruction(packet);
    const std::size_t header = protocol == kV1 ? 4 : 7;
    const std::size_t check = protocol == kV1 ? 1 : 2;
    const auto result =
        wire::decode_instruction(frame(protocol, 7, bytes[header],
                                       Bytes(bytes.begin() + static_cast<long>(header) + 1,
                                             bytes.end() - static_cast<long>(check))));
    INFO(wire::describe(packet));
    REQUIRE(std::holds_alternative<wire::InstructionPacket>(result));
    CHECK(std::get<wire::InstructionPacket>(result) == packet);
  };
  for (const auto& i : both) {
    round_trip(kV1, i);
    round_trip(kV2, i);
  }
  for (const auto& i : v2_only) {
    round_trip(kV2, i);
  }
}
