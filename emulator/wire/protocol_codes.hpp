#pragma once

#include <cstdint>

namespace dxlemu::wire {

/// The protocols of the codec: DYNAMIXEL Protocol 1.0 and 2.0 and Modbus RTU, whose values are the
/// Protocol Type item's values (control table address 13; DYNAMIXEL-P: "10: Modbus-RTU"), and
/// FEETECH's FT-SCS protocol (SCS/STS/SMS/HLS servos). FEETECH's value, 0x46 ('F'), lies outside
/// every range a Protocol Type item accepts (1 ~ 2; XL330/XC330 2 ~ 22; P 2, 10), so no number
/// read from a DYNAMIXEL control table can become it.
enum class Protocol : std::uint8_t { V1 = 1, V2 = 2, Modbus = 10, Feetech = 0x46 };

/// Packet ID that addresses every device on the bus (all three protocols).
inline constexpr std::uint8_t kBroadcastId = 0xFE;

/// Highest unicast Packet ID: protocol2.md "Packet ID" (0 ~ 252), protocol1.md (0 ~ 253) and
/// protocol-ft-scs.md 2 ("The ID range is 0–253").
inline constexpr std::uint8_t kMaxIdV1 = 253;
inline constexpr std::uint8_t kMaxIdV2 = 252;
inline constexpr std::uint8_t kMaxIdFeetech = 253;

/// Modbus RTU addresses (modbus-rtu.md "RTU framing"): 0 is broadcast, 1 ~ 247 one server.
inline constexpr std::uint8_t kModbusBroadcastAddress = 0;
inline constexpr std::uint8_t kMinModbusAddress = 1;
inline constexpr std::uint8_t kMaxModbusAddress = 247;

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

/// Modbus function codes a DYNAMIXEL server answers (modbus-rtu.md "Function codes"); any
/// other code is answered with exception 01.
enum class ModbusFunction : std::uint8_t {
  ReadHoldingRegisters = 0x03,
  ReadInputRegisters = 0x04,
  WriteSingleRegister = 0x06,
  Diagnostics = 0x08,
  WriteMultipleRegisters = 0x10,
  ReadWriteMultipleRegisters = 0x17,
};

/// The byte value of an instruction code.
constexpr std::uint8_t to_byte(InstructionCode code) {
  return static_cast<std::uint8_t>(code);
}

/// The byte value of a FEETECH instruction code.
constexpr std::uint8_t to_byte(FeetechInstructionCode code) {
  return static_cast<std::uint8_t>(code);
}

/// The byte value of a Modbus function code.
constexpr std::uint8_t to_byte(ModbusFunction code) {
  return static_cast<std::uint8_t>(code);
}

}  // namespace dxlemu::wire
