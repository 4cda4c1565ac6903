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

}  // namespace dxlemu::wire
