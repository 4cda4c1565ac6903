#pragma once

#include <string>

#include "wire/instruction.hpp"
#include "wire/status.hpp"

namespace dxlemu::wire {

/// One-line canonical text of a decoded packet, e.g. "id=1 read address=132 length=4" or
/// "id=254 sync_write address=116 length=4 [1: 96 00 00 00] [2: AA 00 00 00]". Decimal IDs,
/// addresses and lengths; data as uppercase hex. The syntax is documented in docs/wire.md and
/// used by the golden vectors in tests/data/golden_packets.txt and by traces.
std::string describe(const InstructionPacket& packet);

/// "id=1 error=0x00 params=06 04 26" (no "params=" when there are none).
std::string describe(const StatusPacket& status);

/// "id=254 fast_reply [3: error=0x00 data=A6 00 00 00] [7: error=0x00 data=1F 08 00 00]".
std::string describe(const FastReply& reply);

}  // namespace dxlemu::wire
