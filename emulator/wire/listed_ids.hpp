#pragma once

#include <cstdint>
#include <vector>

#include "wire/instruction.hpp"

namespace dxlemu::wire {

/// The IDs a Sync or Bulk instruction lists (in order, each once), or empty for any other.
std::vector<std::uint8_t> listed_ids(const InstructionPacket& packet);

}  // namespace dxlemu::wire
