#pragma once

#include <cstdint>

namespace dxlemu::test {

// Status error bytes and a Moving Status bit the servo tests expect, written from the protocol
// pages rather than taken from wire/status_error.hpp, so that a wrong value there fails them.

/// Protocol 2.0 Result Fail (protocol2.md "Error").
inline constexpr std::uint8_t kResultFail = 0x01;
/// Protocol 2.0 Data Range Error (protocol2.md "Error").
inline constexpr std::uint8_t kDataRange = 0x04;
/// Protocol 2.0 Alert bit: set while Hardware Error Status is not 0 (protocol2.md "Error").
inline constexpr std::uint8_t kAlert = 0x80;
/// Moving Status bit 0 of the X and Y series: the profile has reached its goal.
inline constexpr std::int64_t kInPosition = 0x01;

}  // namespace dxlemu::test
