#pragma once

#include <cstdint>
#include <string_view>

namespace dxlemu::wire {

/// The two DYNAMIXEL protocols. Values are the Protocol Type item's values (control table address
/// 13).
enum class Protocol : std::uint8_t { V1 = 1, V2 = 2 };

/// Packet ID that addresses every device on the bus (both protocols).
inline constexpr std::uint8_t kBroadcastId = 0xFE;

/// Highest unicast Packet ID: protocol2.md "Packet ID" (0 ~ 252) and protocol1.md (0 ~ 253).
inline constexpr std::uint8_t kMaxIdV1 = 253;
inline constexpr std::uint8_t kMaxIdV2 = 252;

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

/// The snake_case name of an instruction ("sync_read"), used in traces, errors and the control API;
/// "unknown" for a byte that is not an InstructionCode.
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

/// The byte value of an instruction code.
constexpr std::uint8_t to_byte(InstructionCode code) {
  return static_cast<std::uint8_t>(code);
}

/// True when `id` may appear as a Packet ID of `protocol` (a unicast ID or the broadcast ID).
constexpr bool is_valid_packet_id(Protocol protocol, std::uint8_t id) {
  return id == kBroadcastId || id <= (protocol == Protocol::V1 ? kMaxIdV1 : kMaxIdV2);
}

}  // namespace dxlemu::wire
