#pragma once

#include <cstdint>

namespace dxlemu::wire {

/// Protocol 2.0 error numbers (protocol2.md "Error": bits 6..0 of the status ERR byte).
enum class StatusError : std::uint8_t {
  None = 0x00,
  ResultFail = 0x01,   ///< Failed to process the instruction.
  Instruction = 0x02,  ///< Undefined instruction, or Action without Reg Write.
  Crc = 0x03,          ///< CRC of the instruction packet does not match.
  DataRange = 0x04,    ///< Value outside the item's min/max.
  DataLength = 0x05,   ///< Write shorter than the item.
  DataLimit = 0x06,    ///< Value outside the configured limit.
  Access = 0x07,       ///< Read-only/undefined address, or EEPROM write with torque on.
};

/// Protocol 2.0 Alert bit: set in every status while Hardware Error Status is non-zero.
inline constexpr std::uint8_t kAlertBit = 0x80;

/// The Protocol 2.0 ERR byte for an error number and the alert flag.
constexpr std::uint8_t status_error_byte(StatusError error, bool alert) {
  return static_cast<std::uint8_t>(static_cast<std::uint8_t>(error) | (alert ? kAlertBit : 0));
}

/// Protocol 1.0 error bits (protocol1.md "Error"; bit 7 is always 0).
namespace v1_error {
inline constexpr std::uint8_t kInputVoltage = 1U << 0;
inline constexpr std::uint8_t kAngleLimit = 1U << 1;
inline constexpr std::uint8_t kOverheating = 1U << 2;
inline constexpr std::uint8_t kRange = 1U << 3;
inline constexpr std::uint8_t kChecksum = 1U << 4;
inline constexpr std::uint8_t kOverload = 1U << 5;
inline constexpr std::uint8_t kInstruction = 1U << 6;
}  // namespace v1_error

/// FEETECH status bits: the ERROR byte of an FT-SCS status packet mirrors the "Servo status" item
/// (address 65) of the memory tables. Names after FTServo_Python's ERRBIT_* constants, meanings
/// after the wiki (sts3215.md "3.2 Servo Status"). Bits 4, 6 and 7 are undefined; SCS/SCSCL
/// servos use only bits 0, 2 and 5. Unlike Protocol 1.0 there are no instruction, checksum or
/// range bits.
namespace feetech_error {
inline constexpr std::uint8_t kVoltage = 1U << 0;      ///< ERRBIT_VOLTAGE: input voltage
inline constexpr std::uint8_t kAngleSensor = 1U << 1;  ///< ERRBIT_ANGLE: magnetic encoder
inline constexpr std::uint8_t kOverheat = 1U << 2;     ///< ERRBIT_OVERHEAT: temperature
inline constexpr std::uint8_t kOverCurrent = 1U << 3;  ///< ERRBIT_OVERELE: current
inline constexpr std::uint8_t kOverload = 1U << 5;     ///< ERRBIT_OVERLOAD: load
/// Every bit FEETECH defines.
inline constexpr std::uint8_t kDefinedBits =
    kVoltage | kAngleSensor | kOverheat | kOverCurrent | kOverload;
}  // namespace feetech_error

}  // namespace dxlemu::wire
