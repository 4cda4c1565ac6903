#pragma once

#include <cstdint>
#include <string_view>

namespace dxlemu::wire {

/// The protocols of the codec: DYNAMIXEL Protocol 1.0 and 2.0, whose values are the Protocol Type
/// item's values (control table address 13), and FEETECH's FT-SCS protocol (SCS/STS/SMS/HLS
/// servos). FEETECH's value, 0x46 ('F'), lies outside every range a Protocol Type item accepts
/// (1 ~ 2; XL330/XC330 2 ~ 22), so no number read from a DYNAMIXEL control table can become it.
enum class Protocol : std::uint8_t { V1 = 1, V2 = 2, Feetech = 0x46 };

/// The protocol as users write it: "1.0", "2.0" or "feetech".
constexpr std::string_view protocol_name(Protocol protocol) {
  switch (protocol) {
    case Protocol::V1:
      return "1.0";
    case Protocol::V2:
      return "2.0";
    case Protocol::Feetech:
      return "feetech";
  }
  return "unknown";
}

/// The protocol in messages: "Protocol 1.0", "Protocol 2.0" or "FEETECH".
constexpr std::string_view protocol_title(Protocol protocol) {
  switch (protocol) {
    case Protocol::V1:
      return "Protocol 1.0";
    case Protocol::V2:
      return "Protocol 2.0";
    case Protocol::Feetech:
      return "FEETECH";
  }
  return "unknown protocol";
}

/// The protocol's number where it has one: DYNAMIXEL's 1 and 2 (as the Protocol Type item and
/// the JSON of traces, configs and the control API write them); 0 for FEETECH, which JSON names
/// "feetech" (protocol_name) instead.
constexpr int protocol_number(Protocol protocol) {
  return protocol == Protocol::Feetech ? 0 : static_cast<int>(protocol);
}

/// True for the protocols laid out like Protocol 1.0: header FF FF, one-byte LENGTH, one-byte
/// checksum, no stuffing, one-byte address and length fields, the error byte of a status packet
/// in the instruction position. FEETECH's FT-SCS frame is the 1.0 frame (protocol-ft-scs.md 2, 3).
constexpr bool has_v1_layout(Protocol protocol) {
  return protocol != Protocol::V2;
}

/// Packet ID that addresses every device on the bus (all three protocols).
inline constexpr std::uint8_t kBroadcastId = 0xFE;

/// Highest unicast Packet ID: protocol2.md "Packet ID" (0 ~ 252), protocol1.md (0 ~ 253) and
/// protocol-ft-scs.md 2 ("The ID range is 0–253").
inline constexpr std::uint8_t kMaxIdV1 = 253;
inline constexpr std::uint8_t kMaxIdV2 = 252;
inline constexpr std::uint8_t kMaxIdFeetech = 253;

/// Instruction byte values of both pages (protocol1.md and protocol2.md, "Instruction").
enum class InstructionCode : std::uint8_t {
  Ping = 0x01,
  Read = 0x02,
  Write = 0x03,
  RegWrite = 0x04,
  Action = 0x05,
  FactoryReset = 0x06,
  Reboot = 0x08,
  Clear = 0x10,
  ControlTableBackup = 0x20,
  Status = 0x55,
  SyncRead = 0x82,
  SyncWrite = 0x83,
  FastSyncRead = 0x8A,
  BulkRead = 0x92,
  BulkWrite = 0x93,
  FastBulkRead = 0x9A,
};

/// Instruction byte values of FEETECH's FT-SCS protocol (protocol-ft-scs.md 4 "Instruction types").
/// 0x06 and 0x08 are also DYNAMIXEL codes, with other meanings for 0x06.
enum class FeetechInstructionCode : std::uint8_t {
  Ping = 0x01,
  Read = 0x02,
  Write = 0x03,
  RegWrite = 0x04,
  Action = 0x05,
  ParameterRecovery = 0x06,
  Restart = 0x08,
  ParameterBackup = 0x09,
  StatusReset = 0x0A,
  PositionCalibration = 0x0B,
  SyncRead = 0x82,
  SyncWrite = 0x83,
};

/// The snake_case name of a DYNAMIXEL instruction ("sync_read"), used in traces, errors and the
/// control API; "unknown" for a byte that is not an InstructionCode.
constexpr std::string_view instruction_name(std::uint8_t code) {
  switch (static_cast<InstructionCode>(code)) {
    case InstructionCode::Ping:
      return "ping";
    case InstructionCode::Read:
      return "read";
    case InstructionCode::Write:
      return "write";
    case InstructionCode::RegWrite:
      return "reg_write";
    case InstructionCode::Action:
      return "action";
    case InstructionCode::FactoryReset:
      return "factory_reset";
    case InstructionCode::Reboot:
      return "reboot";
    case InstructionCode::Clear:
      return "clear";
    case InstructionCode::ControlTableBackup:
      return "control_table_backup";
    case InstructionCode::Status:
      return "status";
    case InstructionCode::SyncRead:
      return "sync_read";
    case InstructionCode::SyncWrite:
      return "sync_write";
    case InstructionCode::FastSyncRead:
      return "fast_sync_read";
    case InstructionCode::BulkRead:
      return "bulk_read";
    case InstructionCode::BulkWrite:
      return "bulk_write";
    case InstructionCode::FastBulkRead:
      return "fast_bulk_read";
  }
  return "unknown";
}

/// The snake_case name of a FEETECH instruction; "unknown" for a byte that is not a
/// FeetechInstructionCode. Codes with a DYNAMIXEL twin of the same meaning have its name
/// (0x08 Restart decodes as Reboot: "reboot").
constexpr std::string_view feetech_instruction_name(std::uint8_t code) {
  switch (static_cast<FeetechInstructionCode>(code)) {
    case FeetechInstructionCode::Ping:
      return "ping";
    case FeetechInstructionCode::Read:
      return "read";
    case FeetechInstructionCode::Write:
      return "write";
    case FeetechInstructionCode::RegWrite:
      return "reg_write";
    case FeetechInstructionCode::Action:
      return "action";
    case FeetechInstructionCode::ParameterRecovery:
      return "parameter_recovery";
    case FeetechInstructionCode::Restart:
      return "reboot";
    case FeetechInstructionCode::ParameterBackup:
      return "parameter_backup";
    case FeetechInstructionCode::StatusReset:
      return "status_reset";
    case FeetechInstructionCode::PositionCalibration:
      return "position_calibration";
    case FeetechInstructionCode::SyncRead:
      return "sync_read";
    case FeetechInstructionCode::SyncWrite:
      return "sync_write";
  }
  return "unknown";
}

/// The name of instruction byte `code` in `protocol`. The DYNAMIXEL names do not depend on the
/// version: a 2.0-only code in a 1.0 packet still has its 2.0 name here.
constexpr std::string_view instruction_name(Protocol protocol, std::uint8_t code) {
  return protocol == Protocol::Feetech ? feetech_instruction_name(code) : instruction_name(code);
}

/// The byte value of an instruction code.
constexpr std::uint8_t to_byte(InstructionCode code) {
  return static_cast<std::uint8_t>(code);
}

/// The byte value of a FEETECH instruction code.
constexpr std::uint8_t to_byte(FeetechInstructionCode code) {
  return static_cast<std::uint8_t>(code);
}

/// Highest unicast Packet ID of `protocol`.
constexpr std::uint8_t max_unicast_id(Protocol protocol) {
  switch (protocol) {
    case Protocol::V1:
      return kMaxIdV1;
    case Protocol::V2:
      return kMaxIdV2;
    case Protocol::Feetech:
      return kMaxIdFeetech;
  }
  return kMaxIdV2;
}

/// True when `id` may appear as a Packet ID of `protocol` (a unicast ID or the broadcast ID).
constexpr bool is_valid_packet_id(Protocol protocol, std::uint8_t id) {
  return id == kBroadcastId || id <= max_unicast_id(protocol);
}

}  // namespace dxlemu::wire
