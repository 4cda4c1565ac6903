#pragma once

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "wire/protocol.hpp"

namespace dxlemu::wire {

/// Ping (0x01): is a device there? 2.0 replies carry model number and firmware version.
struct Ping {
  bool operator==(const Ping&) const = default;
};

/// Read (0x02): `length` bytes from `address`.
struct Read {
  std::uint16_t address = 0;
  std::uint16_t length = 0;
  bool operator==(const Read&) const = default;
};

/// Write (0x03): `data` to consecutive addresses from `address`.
struct Write {
  std::uint16_t address = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const Write&) const = default;
};

/// Reg Write (0x04): like Write, but held until Action.
struct RegWrite {
  std::uint16_t address = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const RegWrite&) const = default;
};

/// Action (0x05): executes the registered Reg Write.
struct Action {
  bool operator==(const Action&) const = default;
};

/// Factory Reset options (protocol2.md "Factory Reset (0x06)"). Protocol 1.0 has no option byte
/// and always resets everything, which decodes as kResetAll.
namespace factory_reset {
inline constexpr std::uint8_t kResetAll = 0xFF;
inline constexpr std::uint8_t kResetAllButId = 0x01;
inline constexpr std::uint8_t kResetAllButIdAndBaud = 0x02;
}  // namespace factory_reset

/// Factory Reset (0x06) with one of the factory_reset options.
struct FactoryReset {
  std::uint8_t option = factory_reset::kResetAll;
  bool operator==(const FactoryReset&) const = default;
};

/// Reboot (0x08); FEETECH's Restart (0x08) decodes as this too.
struct Reboot {
  bool operator==(const Reboot&) const = default;
};

/// Clear (0x10, 2.0 only). Option 0x01 (reset multi-turn position) carries the fixed bytes
/// 44 58 4C 22 in `data`; other options are reserved and keep whatever bytes followed.
struct Clear {
  std::uint8_t option = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const Clear&) const = default;
};

/// Control Table Backup (0x20, 2.0 only): option 0x01 stores, 0x02 restores; both carry the fixed
/// bytes 43 54 52 4C in `data`. Other options are reserved and keep whatever bytes followed.
struct ControlTableBackup {
  std::uint8_t option = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const ControlTableBackup&) const = default;
};

/// Sync Read (0x82, 2.0 and FEETECH): the same `length` bytes from `address` of every device in
/// `ids`.
struct SyncRead {
  std::uint16_t address = 0;
  std::uint16_t length = 0;
  std::vector<std::uint8_t> ids;
  bool operator==(const SyncRead&) const = default;
};

/// Fast Sync Read (0x8A, 2.0): Sync Read answered with one combined status packet.
struct FastSyncRead : SyncRead {
  bool operator==(const FastSyncRead&) const = default;
};

/// One device's part of a Sync Write.
struct SyncWriteTarget {
  std::uint8_t id = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const SyncWriteTarget&) const = default;
};

/// Sync Write (0x83): `length` bytes to `address` of each target.
struct SyncWrite {
  std::uint16_t address = 0;
  std::uint16_t length = 0;
  std::vector<SyncWriteTarget> targets;
  bool operator==(const SyncWrite&) const = default;
};

/// One device's part of a Bulk Read.
struct BulkReadTarget {
  std::uint8_t id = 0;
  std::uint16_t address = 0;
  std::uint16_t length = 0;
  bool operator==(const BulkReadTarget&) const = default;
};

/// The byte Protocol 1.0's Bulk Read parameters start with (protocol1.md "Bulk Read").
inline constexpr std::uint8_t kV1BulkReadLeadByte = 0x00;

/// Bulk Read (0x92): a different address and length per device. Protocol 1.0 lays the
/// parameters out differently (kV1BulkReadLeadByte, then length, ID, address per device); the
/// fields are the same.
struct BulkRead {
  std::vector<BulkReadTarget> targets;
  bool operator==(const BulkRead&) const = default;
};

/// Fast Bulk Read (0x9A, 2.0): Bulk Read answered with one combined status packet.
struct FastBulkRead : BulkRead {
  bool operator==(const FastBulkRead&) const = default;
};

/// One device's part of a Bulk Write.
struct BulkWriteTarget {
  std::uint8_t id = 0;
  std::uint16_t address = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const BulkWriteTarget&) const = default;
};

/// Bulk Write (0x93, 2.0): a different address and data per device.
struct BulkWrite {
  std::vector<BulkWriteTarget> targets;
  bool operator==(const BulkWrite&) const = default;
};

/// FEETECH Parameter recovery (0x06): "Restore all servo parameters except the ID" from what
/// Parameter backup stored (protocol-ft-scs.md 4.10). Not a DYNAMIXEL Factory Reset, which
/// restores the factory values. No parameters.
struct ParameterRecovery {
  bool operator==(const ParameterRecovery&) const = default;
};

/// FEETECH Parameter backup (0x09): stores the current parameters for Parameter recovery
/// (protocol-ft-scs.md 4.11). No parameters.
struct ParameterBackup {
  bool operator==(const ParameterBackup&) const = default;
};

/// FEETECH RESET (0x0A): "Reset the servo status (reset the servo turn count)"
/// (protocol-ft-scs.md 4.8). No parameters.
struct StatusReset {
  bool operator==(const StatusReset&) const = default;
};

/// FEETECH Position calibration (0x0B): "recalibrate the current position to the set value", or
/// to the middle position when no value is given (protocol-ft-scs.md 4.9).
struct PositionCalibration {
  /// The set value, a 16-bit word sent low byte first (Example 11: 00 04 = 1024); nullopt for
  /// the middle position.
  std::optional<std::uint16_t> position;
  bool operator==(const PositionCalibration&) const = default;
};

/// Modbus Read/Write Multiple Registers (0x17): `write` is done first, then `read` answered
/// (modbus-rtu.md "Function codes"). Addresses and lengths are control-table bytes, as in Read
/// and Write.
struct WriteRead {
  Write write;
  Read read;
  bool operator==(const WriteRead&) const = default;
};

/// Modbus Diagnostics (0x08) sub-function 0x0000, Return Query Data: `data` comes back as it
/// was sent.
struct Echo {
  std::vector<std::uint8_t> data;
  bool operator==(const Echo&) const = default;
};

/// An instruction byte this protocol does not define; a servo answers it with Instruction Error.
struct UnknownInstruction {
  std::uint8_t instruction = 0;
  std::vector<std::uint8_t> params;
  bool operator==(const UnknownInstruction&) const = default;
};

/// Every instruction of protocol1.md, protocol2.md, protocol-ft-scs.md and modbus-rtu.md. Modbus
/// register reads and writes decode as Read and Write of the control-table bytes they cover.
using Instruction =
    std::variant<Ping, Read, Write, RegWrite, Action, FactoryReset, Reboot, Clear,
                 ControlTableBackup, SyncRead, FastSyncRead, SyncWrite, BulkRead, FastBulkRead,
                 BulkWrite, ParameterRecovery, ParameterBackup, StatusReset, PositionCalibration,
                 WriteRead, Echo, UnknownInstruction>;

/// A decoded instruction packet: who it is for and what it asks.
struct InstructionPacket {
  Protocol protocol = Protocol::V2;
  std::uint8_t id = 0;
  Instruction instruction;
  bool operator==(const InstructionPacket&) const = default;
};

}  // namespace dxlemu::wire
