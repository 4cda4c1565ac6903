#pragma once

// One row per protocol: every fact about a protocol that a layer outside wire/ needs (its
// spellings, framing, IDs, instructions, status vocabulary and the few rules that differ between
// protocols) is a field here, so that the bus, the servos, the configs, the CLI, the fault rules
// and the traces read a row instead of switching on the protocol. Adding a protocol is adding a
// row (docs/architecture.md "Adding a protocol").

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string_view>
#include <utility>

#include "sim/sim_time.hpp"
#include "wire/protocol_codes.hpp"

namespace dxlemu::wire {

/// How a frame's end is found.
enum class Delimiting : std::uint8_t {
  LengthField,  ///< a header, the ID, then a LENGTH field counting the rest (DYNAMIXEL, FEETECH)
  Silence,      ///< no header or length: a frame ends at a silence of `silence_chars` characters
};

/// The integrity check at a frame's end.
enum class CheckKind : std::uint8_t {
  Sum8,          ///< one byte: ~(sum of ID .. last parameter) (protocol1.md "Check Sum")
  Crc16Robotis,  ///< two bytes, low first: polynomial 0x8005 over header .. last parameter
  Crc16Modbus,   ///< two bytes, low first: polynomial 0xA001 reflected over address .. data
};

/// How a protocol lays out a frame: what a framer and an encoder need.
struct FrameShape {
  Delimiting delimiting = Delimiting::LengthField;
  /// Header bytes; `header_size` of them are used (none for a silence-delimited protocol).
  std::array<std::uint8_t, 4> header{};
  std::uint8_t header_size = 0;
  /// Width of the LENGTH field, and of address and data-length fields in parameters (1 or 2).
  std::uint8_t field_bytes = 1;
  /// Smallest and largest LENGTH value: a header announcing more is an impossible length.
  std::uint16_t min_length = 0;
  std::uint16_t max_length = 0;
  CheckKind check = CheckKind::Sum8;
  /// Byte stuffing of the instruction and parameters (protocol2.md "Byte Stuffing").
  bool stuffing = false;
  /// A partial packet is dropped when the gap to the next byte exceeds this.
  sim::SimDuration inter_byte_timeout{};
  /// For Delimiting::Silence: the silence that ends a frame, in tenths of a character time
  /// (Modbus RTU: 35, "3.5 character times"); 0 otherwise.
  std::uint8_t silence_tenths = 0;
  /// The status packet's error byte sits where an instruction packet has its instruction byte
  /// (1.0 and FEETECH); otherwise the status has an instruction byte (0x55) then the error byte.
  bool error_in_instruction_position = true;
  /// For Delimiting::Silence: a gap longer than this, in tenths of a character time, breaks the
  /// frame it falls in (Modbus RTU: 15, "1.5 character times"); 0 otherwise.
  std::uint8_t gap_tenths = 0;
  /// For Delimiting::Silence: bits of one character in the timing rule (Modbus RTU: 11), and the
  /// rate above which the silence and the gap are fixed times instead (19,200 bit/s: 1,750 and
  /// 750 us), 0 for none.
  std::uint8_t char_bits = 0;
  std::uint32_t fixed_timing_above_bps = 0;
  sim::SimDuration fixed_silence{};
  sim::SimDuration fixed_gap{};
};

/// What one instruction byte is, for names, traces and the bus's addressing rules.
enum class InstructionRole : std::uint8_t {
  Single,      ///< addressed to one ID (or broadcast)
  GroupRead,   ///< Sync/Bulk Read: one packet, replies from each listed ID
  GroupWrite,  ///< Sync/Bulk Write: one packet, data for each listed ID, no replies
  Status,      ///< the status marker (2.0's 0x55), not an instruction a client sends
};

/// One instruction of a protocol.
struct InstructionInfo {
  std::uint8_t code = 0;
  /// snake_case, as traces, fault rules and the control API write it ("sync_read").
  std::string_view name;
  /// As the protocol's manual names it ("Sync Read"; FEETECH's 0x08 "Restart").
  std::string_view title;
  InstructionRole role = InstructionRole::Single;
};

/// What a servo's answer to one instruction comes to, whatever the protocol: each protocol's
/// status vocabulary turns it into its own error byte (or exception code).
enum class Outcome : std::uint8_t {
  Ok,
  Access,              ///< undefined or read-only address, EEPROM locked
  DataLength,          ///< a write covering part of a multi-byte item
  DataRange,           ///< a value outside the item's range, or a parameter out of range
  DataLimit,           ///< a value beyond the item that limits it
  AngleLimit,          ///< Goal Position outside the angle limits in joint mode
  ResultFail,          ///< the servo cannot do it now
  UnknownInstruction,  ///< an instruction byte the servo does not execute
  BadCheck,            ///< the checksum or CRC did not match
  BadParameters,       ///< parameters that do not make the instruction (wrong count)
  /// A Read, or a device's part of a Sync/Bulk Read, reaching outside the table (past its end,
  /// in whole or in part) or asking more than a status can carry.
  ReadOutside,
  NothingRegistered,  ///< Action with no Reg Write waiting
  Locked,             ///< an EEPROM item while the EEPROM is locked (torque on, or Lock)
};

/// Number of Outcome values.
inline constexpr std::size_t kOutcomeCount = 13;

/// How a protocol's status carries an outcome.
enum class StatusShape : std::uint8_t {
  /// 2.0: an error number in bits 6..0, plus the alert bit while a hardware error lasts.
  ErrorNumber,
  /// 1.0: one bit per kind of error; the device's hardware error bits are ORed in.
  ErrorBits,
  /// FEETECH: the device's status item; a refusal adds the bit the model file names for its
  /// RefusalClass, or silences the status (codes are RefusalClass values).
  DeviceStatus,
  /// Modbus RTU: a refusal is an exception response (function | 0x80, exception code) and no
  /// error byte rides on a normal response (codes are exception codes, 0: a normal response).
  ExceptionCode,
};

/// For StatusShape::DeviceStatus: which of the model's refusal answers an outcome gets. None: it
/// is no refusal there, only the live status is sent.
enum class RefusalClass : std::uint8_t {
  None,
  Range,        ///< a write, or an instruction's setting, the device refuses
  Instruction,  ///< an instruction the device does not know, or cannot make out
  Checksum,     ///< a packet with a broken check, sent to the device's ID
  Read,         ///< a read outside the table (Outcome::ReadOutside)
};

/// Number of RefusalClass values.
inline constexpr std::size_t kRefusalClassCount = 5;

/// What a StatusShape::DeviceStatus device does about one class of refusal: a status whose
/// error byte carries `bit` (0: none) beside the live status, or, when `silent`, no status.
struct RefusalAnswer {
  bool silent = false;
  std::uint8_t bit = 0;
  constexpr bool operator==(const RefusalAnswer&) const = default;
};

/// The answer that sends no status.
inline constexpr RefusalAnswer kSilentRefusal{.silent = true, .bit = 0};

/// A protocol's status vocabulary: how each Outcome becomes its error code.
struct StatusVocabulary {
  StatusShape shape = StatusShape::ErrorNumber;
  /// The code of each outcome, indexed by Outcome (its meaning depends on `shape`).
  std::array<std::uint8_t, kOutcomeCount> code{};
  /// ErrorNumber: the bit set while the device has a hardware error.
  std::uint8_t alert_bit = 0;
  /// False when a packet with a bad check is ignored rather than answered with an error.
  bool answers_bad_check = true;
};

/// What a device adds to every status besides the outcome: its standing faults.
struct DeviceFaults {
  bool alert = false;            ///< ErrorNumber: a hardware error is latched
  std::uint8_t status_bits = 0;  ///< ErrorBits, DeviceStatus: the live hardware/status bits
  /// DeviceStatus: the answer per RefusalClass (indexed by its value).
  std::array<RefusalAnswer, kRefusalClassCount> refusals{};
};

/// Everything about one protocol.
struct ProtocolTraits {
  Protocol protocol = Protocol::V2;
  /// As users write it in messages and the docs: "1.0", "2.0", "feetech".
  std::string_view name;
  /// In sentences: "Protocol 1.0", "FEETECH".
  std::string_view title;
  /// As the CLI (`--protocol`), model files, configs, traces and the control API spell it:
  /// "1", "2" (JSON: the number) or "feetech" (JSON: the string).
  std::string_view spelling;
  /// DYNAMIXEL's number, as JSON writes it; 0 when JSON spells the protocol by name.
  int number = 0;
  /// The Protocol Type item's value that selects it (1, 2; Modbus RTU 10); 0 for none.
  int type_value = 0;
  /// Who makes the devices that speak it, as model::maker_name writes it: "ROBOTIS", "FEETECH".
  std::string_view maker;
  FrameShape frame;
  /// Lowest and highest unicast ID, and the ID every device hears.
  std::uint8_t min_unicast_id = 0;
  std::uint8_t max_unicast_id = 0;
  std::uint8_t broadcast_id = kBroadcastId;
  /// Every instruction byte the protocol names.
  std::span<const InstructionInfo> instructions;
  StatusVocabulary status;
  /// Broadcast Ping replies come one slot per ID in order (2.0); otherwise at once, colliding.
  bool chained_broadcast_ping = false;
  /// A Ping's status carries model number and firmware version (2.0).
  bool ping_reports_model = false;
  /// Factory Reset may be broadcast (2.0, except option 0xFF); 1.0 refuses it.
  bool broadcast_factory_reset = false;
  /// A write must cover whole items (2.0 "Data Length Error"); otherwise partial writes land.
  bool whole_item_writes = false;
  /// Bulk Read executes only on models whose family supports it (1.0's Bulk Read).
  bool bulk_read_needs_support = false;
  /// 0: reads and writes address bytes. 2: they address registers of two bytes (Modbus RTU),
  /// and a register write skips a byte no item of the protocol can take (absent from its map,
  /// read-only, or no item) beside one that can (docs/modbus.md "The register map").
  std::uint8_t register_bytes = 0;
};

// DYNAMIXEL's instruction names do not depend on the version: a 2.0-only code in a 1.0 packet
// still has its 2.0 name (the decoder refuses it there).
inline constexpr std::array kDynamixelInstructions{
    InstructionInfo{0x01, "ping", "Ping"},
    InstructionInfo{0x02, "read", "Read"},
    InstructionInfo{0x03, "write", "Write"},
    InstructionInfo{0x04, "reg_write", "Reg Write"},
    InstructionInfo{0x05, "action", "Action"},
    InstructionInfo{0x06, "factory_reset", "Factory Reset"},
    InstructionInfo{0x08, "reboot", "Reboot"},
    InstructionInfo{0x10, "clear", "Clear"},
    InstructionInfo{0x20, "control_table_backup", "Control Table Backup"},
    InstructionInfo{0x55, "status", "Status", InstructionRole::Status},
    InstructionInfo{0x82, "sync_read", "Sync Read", InstructionRole::GroupRead},
    InstructionInfo{0x83, "sync_write", "Sync Write", InstructionRole::GroupWrite},
    InstructionInfo{0x8A, "fast_sync_read", "Fast Sync Read", InstructionRole::GroupRead},
    InstructionInfo{0x92, "bulk_read", "Bulk Read", InstructionRole::GroupRead},
    InstructionInfo{0x93, "bulk_write", "Bulk Write", InstructionRole::GroupWrite},
    InstructionInfo{0x9A, "fast_bulk_read", "Fast Bulk Read", InstructionRole::GroupRead},
};

// protocol-ft-scs.md 4 "Instruction types". Codes with a DYNAMIXEL twin of the same meaning have
// its name (0x08 Restart is "reboot").
inline constexpr std::array kFeetechInstructions{
    InstructionInfo{0x01, "ping", "Ping"},
    InstructionInfo{0x02, "read", "Read"},
    InstructionInfo{0x03, "write", "Write"},
    InstructionInfo{0x04, "reg_write", "Reg Write"},
    InstructionInfo{0x05, "action", "Action"},
    InstructionInfo{0x06, "parameter_recovery", "Parameter Recovery"},
    InstructionInfo{0x08, "reboot", "Restart"},
    InstructionInfo{0x09, "parameter_backup", "Parameter Backup"},
    InstructionInfo{0x0A, "status_reset", "Status Reset"},
    InstructionInfo{0x0B, "position_calibration", "Position Calibration"},
    InstructionInfo{0x82, "sync_read", "Sync Read", InstructionRole::GroupRead},
    InstructionInfo{0x83, "sync_write", "Sync Write", InstructionRole::GroupWrite},
};

// modbus-rtu.md "Function codes a register server offers"; the names are the Modbus
// specification's.
inline constexpr std::array kModbusFunctions{
    InstructionInfo{0x03, "read_holding_registers", "Read Holding Registers"},
    InstructionInfo{0x04, "read_input_registers", "Read Input Registers"},
    InstructionInfo{0x06, "write_single_register", "Write Single Register"},
    InstructionInfo{0x08, "diagnostics", "Diagnostics"},
    InstructionInfo{0x10, "write_multiple_registers", "Write Multiple Registers"},
    InstructionInfo{0x17, "read_write_multiple_registers", "Read/Write Multiple Registers"},
};

/// Helpers and constants the rows are written with.
namespace detail {

/// A status vocabulary's codes from (outcome, code) pairs; outcomes not listed get 0.
constexpr std::array<std::uint8_t, kOutcomeCount> codes(
    std::initializer_list<std::pair<Outcome, std::uint8_t>> pairs) {
  std::array<std::uint8_t, kOutcomeCount> out{};
  for (const auto& [outcome, code] : pairs) {
    out[static_cast<std::size_t>(outcome)] = code;
  }
  return out;
}

/// Bit `n` of an error byte.
constexpr std::uint8_t bit(int n) {
  return static_cast<std::uint8_t>(1U << n);
}

/// A RefusalClass as a DeviceStatus code.
constexpr std::uint8_t refusal(RefusalClass c) {
  return static_cast<std::uint8_t>(c);
}

// protocol1.md / protocol2.md "Byte to Byte Time". FEETECH documents none; its frame is the 1.0
// frame, so a FEETECH framer waits as long as a 1.0 servo (docs/wire.md "FEETECH").
inline constexpr sim::SimDuration kV1InterByteTimeout = std::chrono::milliseconds(100);
inline constexpr sim::SimDuration kV2InterByteTimeout = std::chrono::microseconds(1500);

// A Protocol 2.0 LENGTH is 16 bits, but no ROBOTIS controller sends packets anywhere near that:
// the DynamixelSDK's buffers hold 1 KiB. We accept packets up to 4 KiB on the wire (e.g. a Sync
// Write of 4 bytes to all 253 IDs is 1.3 KiB) and call anything longer an impossible length.
inline constexpr std::uint16_t kV2MaxPacketBytes = 4096;
inline constexpr std::uint16_t kV2HeaderIdLengthBytes = 7;  // FF FF FD 00 ID LEN_L LEN_H

// A Modbus RTU frame: address, function code and CRC at least; "at most 256 bytes".
inline constexpr std::uint16_t kModbusMinFrame = 4;
inline constexpr std::uint16_t kModbusMaxFrame = 256;

// The 1.0 frame (protocol1.md "Instruction Packet"), FEETECH's too (protocol-ft-scs.md 2, 3):
// "Length = number of Parameters + 2" (instruction + checksum).
inline constexpr FrameShape kV1Frame{Delimiting::LengthField,
                                     {0xFF, 0xFF},
                                     2,
                                     1,
                                     2,
                                     0xFF,
                                     CheckKind::Sum8,
                                     false,
                                     kV1InterByteTimeout,
                                     0,
                                     true};

}  // namespace detail

/// The protocols, in the order a bus offers them the line.
inline constexpr std::array kProtocolTable{
    ProtocolTraits{
        .protocol = Protocol::V1,
        .name = "1.0",
        .title = "Protocol 1.0",
        .spelling = "1",
        .number = 1,
        .type_value = 1,
        .maker = "ROBOTIS",
        .frame = detail::kV1Frame,
        .max_unicast_id = kMaxIdV1,
        .instructions = kDynamixelInstructions,
        // protocol1.md "Error": hardware bits 0 (voltage), 2 (overheating), 5 (overload) are
        // the device's; the others name the refusal. 1.0 has no access, length or limit
        // errors: they are all the Range Error bit, except Angle Limit.
        .status = {StatusShape::ErrorBits,
                   detail::codes({{Outcome::Access, detail::bit(3)},
                                  {Outcome::DataLength, detail::bit(3)},
                                  {Outcome::DataRange, detail::bit(3)},
                                  {Outcome::DataLimit, detail::bit(3)},
                                  {Outcome::AngleLimit, detail::bit(1)},
                                  {Outcome::ResultFail, detail::bit(3)},
                                  {Outcome::UnknownInstruction, detail::bit(6)},
                                  {Outcome::BadCheck, detail::bit(4)},
                                  {Outcome::BadParameters, detail::bit(6)},
                                  {Outcome::ReadOutside, detail::bit(3)},
                                  {Outcome::NothingRegistered, detail::bit(6)},
                                  {Outcome::Locked, detail::bit(3)}}),
                   0, true},
        .bulk_read_needs_support = true,
    },
    ProtocolTraits{
        .protocol = Protocol::V2,
        .name = "2.0",
        .title = "Protocol 2.0",
        .spelling = "2",
        .number = 2,
        .type_value = 2,
        .maker = "ROBOTIS",
        // protocol2.md "Instruction Packet": "Length = the number of Parameters + 3"
        // (instruction + CRC).
        .frame = {Delimiting::LengthField,
                  {0xFF, 0xFF, 0xFD, 0x00},
                  4,
                  2,
                  3,
                  detail::kV2MaxPacketBytes - detail::kV2HeaderIdLengthBytes,
                  CheckKind::Crc16Robotis,
                  true,
                  detail::kV2InterByteTimeout,
                  0,
                  false},
        .max_unicast_id = kMaxIdV2,
        .instructions = kDynamixelInstructions,
        // protocol2.md "Error": error numbers; an Angle Limit refusal is a Data Limit Error;
        // parameters that do not make the instruction are a Data Length Error; a read outside
        // the table is an Access Error, Action without Reg Write an Instruction Error.
        .status = {StatusShape::ErrorNumber,
                   detail::codes({{Outcome::ResultFail, 0x01},
                                  {Outcome::UnknownInstruction, 0x02},
                                  {Outcome::NothingRegistered, 0x02},
                                  {Outcome::BadCheck, 0x03},
                                  {Outcome::DataRange, 0x04},
                                  {Outcome::DataLength, 0x05},
                                  {Outcome::BadParameters, 0x05},
                                  {Outcome::DataLimit, 0x06},
                                  {Outcome::AngleLimit, 0x06},
                                  {Outcome::Access, 0x07},
                                  {Outcome::ReadOutside, 0x07},
                                  {Outcome::Locked, 0x07}}),
                   0x80, true},
        .chained_broadcast_ping = true,
        .ping_reports_model = true,
        .broadcast_factory_reset = true,
        .whole_item_writes = true,
    },
    ProtocolTraits{
        .protocol = Protocol::Feetech,
        .name = "feetech",
        .title = "FEETECH",
        .spelling = "feetech",
        .number = 0,
        .maker = "FEETECH",
        .frame = detail::kV1Frame,
        .max_unicast_id = kMaxIdFeetech,
        .instructions = kFeetechInstructions,
        // The error byte mirrors the Servo status item; FEETECH documents no refusal bits, so a
        // model file says what each class of refusal gets: a bit, none, or no status at all
        // (docs/feetech.md "Refusals"). Action with nothing registered is no refusal: it applies
        // nothing and is answered as any Action.
        .status = {StatusShape::DeviceStatus,
                   detail::codes(
                       {{Outcome::Access, detail::refusal(RefusalClass::Range)},
                        {Outcome::DataLength, detail::refusal(RefusalClass::Range)},
                        {Outcome::DataRange, detail::refusal(RefusalClass::Range)},
                        {Outcome::DataLimit, detail::refusal(RefusalClass::Range)},
                        {Outcome::AngleLimit, detail::refusal(RefusalClass::Range)},
                        {Outcome::ResultFail, detail::refusal(RefusalClass::Range)},
                        {Outcome::UnknownInstruction, detail::refusal(RefusalClass::Instruction)},
                        {Outcome::BadCheck, detail::refusal(RefusalClass::Checksum)},
                        {Outcome::BadParameters, detail::refusal(RefusalClass::Instruction)},
                        {Outcome::ReadOutside, detail::refusal(RefusalClass::Read)},
                        {Outcome::NothingRegistered, detail::refusal(RefusalClass::None)},
                        {Outcome::Locked, detail::refusal(RefusalClass::Range)}}),
                   0, true},
    },
    ProtocolTraits{
        .protocol = Protocol::Modbus,
        .name = "modbus",
        .title = "Modbus RTU",
        .spelling = "modbus",
        .number = 0,
        .type_value = 10,
        .maker = "ROBOTIS",
        // modbus-rtu.md "RTU framing": address, function, data (0 ~ 252), CRC low byte first; a
        // frame ends at 3.5 character times of silence, a gap over 1.5 breaks it; above
        // 19,200 bit/s the silence is 1,750 us and the gap 750 us. LENGTH bounds here are the
        // whole frame's: address, function and CRC at least, 256 bytes at most.
        .frame = {.delimiting = Delimiting::Silence,
                  .header = {},
                  .header_size = 0,
                  .field_bytes = 2,
                  .min_length = detail::kModbusMinFrame,
                  .max_length = detail::kModbusMaxFrame,
                  .check = CheckKind::Crc16Modbus,
                  .stuffing = false,
                  .inter_byte_timeout = {},
                  .silence_tenths = 35,
                  .error_in_instruction_position = false,
                  .gap_tenths = 15,
                  .char_bits = 11,
                  .fixed_timing_above_bps = 19200,
                  .fixed_silence = std::chrono::microseconds(1750),
                  .fixed_gap = std::chrono::microseconds(750)},
        .min_unicast_id = kMinModbusAddress,
        .max_unicast_id = kMaxModbusAddress,
        .broadcast_id = kModbusBroadcastAddress,
        .instructions = kModbusFunctions,
        // Exception codes (modbus-rtu.md "Exception responses"; choices in docs/modbus.md): 01
        // for a function it does not serve; 02 for an address the map refuses, a write into
        // part of an item, a read outside the table; 03 for a value out of range or a malformed
        // request; 04 when the device cannot do it now (EEPROM locked while torque is on). A
        // frame with a bad CRC is ignored.
        .status = {StatusShape::ExceptionCode,
                   detail::codes({{Outcome::Access, 0x02},
                                  {Outcome::DataLength, 0x02},
                                  {Outcome::DataRange, 0x03},
                                  {Outcome::DataLimit, 0x03},
                                  {Outcome::AngleLimit, 0x03},
                                  {Outcome::ResultFail, 0x04},
                                  {Outcome::UnknownInstruction, 0x01},
                                  {Outcome::BadCheck, 0x04},
                                  {Outcome::BadParameters, 0x03},
                                  {Outcome::ReadOutside, 0x02},
                                  {Outcome::NothingRegistered, 0x01},
                                  {Outcome::Locked, 0x04}}),
                   0, false},
        .whole_item_writes = true,
        .register_bytes = 2,
    },
};

/// Number of protocols.
inline constexpr std::size_t kProtocolCount = kProtocolTable.size();

/// The protocol a packet, status or setting without one is taken to have: DYNAMIXEL Protocol
/// 2.0 (also what an XL330/XC330 falls back to without an RC signal).
inline constexpr Protocol kDefaultProtocol = Protocol::V2;

/// The position of `protocol`'s row in kProtocolTable (an index for per-protocol arrays).
constexpr std::size_t protocol_index(Protocol protocol) {
  for (std::size_t i = 0; i < kProtocolTable.size(); ++i) {
    if (kProtocolTable[i].protocol == protocol) {
      return i;
    }
  }
  return protocol_index(kDefaultProtocol);
}

/// The row of `protocol`.
constexpr const ProtocolTraits& traits(Protocol protocol) {
  return kProtocolTable[protocol_index(protocol)];
}

/// The protocol spelled `spelling` ("1", "2", "feetech"); nullopt for none.
constexpr std::optional<Protocol> protocol_from_spelling(std::string_view spelling) {
  for (const ProtocolTraits& row : kProtocolTable) {
    if (row.spelling == spelling) {
      return row.protocol;
    }
  }
  return std::nullopt;
}

/// The protocol with DYNAMIXEL number `number` (a JSON number); nullopt when no protocol has it.
constexpr std::optional<Protocol> protocol_from_number(std::int64_t number) {
  for (const ProtocolTraits& row : kProtocolTable) {
    if (row.number != 0 && row.number == number) {
      return row.protocol;
    }
  }
  return std::nullopt;
}

/// The protocol a Protocol Type item's value selects; nullopt when no protocol of the bus has
/// it (S.BUS, iBUS, RC-PWM on an XL330).
constexpr std::optional<Protocol> protocol_from_type_value(std::int64_t value) {
  for (const ProtocolTraits& row : kProtocolTable) {
    if (row.type_value != 0 && row.type_value == value) {
      return row.protocol;
    }
  }
  return std::nullopt;
}

/// The lowest DYNAMIXEL number a protocol has (1).
constexpr int lowest_protocol_number() {
  int out = 0;
  for (const ProtocolTraits& row : kProtocolTable) {
    if (row.number != 0 && (out == 0 || row.number < out)) {
      out = row.number;
    }
  }
  return out;
}

/// The highest DYNAMIXEL number a protocol has.
constexpr int highest_protocol_number() {
  int out = 0;
  for (const ProtocolTraits& row : kProtocolTable) {
    out = row.number > out ? row.number : out;
  }
  return out;
}

/// The highest unicast ID any protocol has (253): the widest range an ID setting may take.
constexpr std::uint8_t highest_unicast_id() {
  std::uint8_t out = 0;
  for (const ProtocolTraits& row : kProtocolTable) {
    out = row.max_unicast_id > out ? row.max_unicast_id : out;
  }
  return out;
}

/// The info of instruction byte `code` in `protocol`; nullptr when the protocol names none.
constexpr const InstructionInfo* instruction_info(Protocol protocol, std::uint8_t code) {
  for (const InstructionInfo& info : traits(protocol).instructions) {
    if (info.code == code) {
      return &info;
    }
  }
  return nullptr;
}

/// The status error byte of `outcome` in `protocol`, with the device's standing faults.
constexpr std::uint8_t status_error_byte(Protocol protocol, Outcome outcome,
                                         const DeviceFaults& device) {
  const StatusVocabulary& v = traits(protocol).status;
  const std::uint8_t code = v.code[static_cast<std::size_t>(outcome)];
  switch (v.shape) {
    case StatusShape::ErrorNumber:
      return static_cast<std::uint8_t>(code | (device.alert ? v.alert_bit : 0));
    case StatusShape::ErrorBits:
      return static_cast<std::uint8_t>(code | device.status_bits);
    case StatusShape::DeviceStatus:
      return static_cast<std::uint8_t>(device.refusals[code].bit | device.status_bits);
    case StatusShape::ExceptionCode:
      return code;
  }
  return code;
}

/// True when `id` is the ID every device of `protocol` hears (0xFE; Modbus RTU: 0).
constexpr bool is_broadcast(Protocol protocol, std::uint8_t id) {
  return id == traits(protocol).broadcast_id;
}

/// True when the device sends no status at all for `outcome` in `protocol` (a DeviceStatus
/// refusal class it answers with silence); the other shapes always answer.
constexpr bool silences(Protocol protocol, Outcome outcome, const DeviceFaults& device) {
  const StatusVocabulary& v = traits(protocol).status;
  return v.shape == StatusShape::DeviceStatus &&
         device.refusals[v.code[static_cast<std::size_t>(outcome)]].silent;
}

}  // namespace dxlemu::wire
