#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "wire/instruction.hpp"

namespace dxlemu::faults {

/// The control-table addresses `packet` reads or writes, first and last. For Bulk Read/Write,
/// the part of servo `id` (or, without an ID, the span covering every part). Nullopt for
/// instructions without an address, or a zero length.
std::optional<std::pair<std::uint16_t, std::uint16_t>> span_of(
    const wire::InstructionPacket& packet, std::optional<std::uint8_t> id = std::nullopt);

}  // namespace dxlemu::faults
