#pragma once

#include <cstdint>
#include <span>

namespace dxlemu::wire {

/// The Protocol 1.0 checksum of a packet body (ID, Length, Instruction or Error, Parameters):
/// ~(sum of the bytes), low byte only (protocol1.md "Checksum").
std::uint8_t v1_checksum(std::span<const std::uint8_t> body);

}  // namespace dxlemu::wire
