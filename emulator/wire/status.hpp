#pragma once

#include <cstdint>
#include <vector>

#include "wire/protocol.hpp"

namespace dxlemu::wire {

/// A status (return) packet of either protocol.
struct StatusPacket {
  Protocol protocol = Protocol::V2;
  std::uint8_t id = 0;
  /// 2.0: alert bit and error number (status_error.hpp); 1.0: the error bit field (v1_error).
  std::uint8_t error = 0;
  std::vector<std::uint8_t> params;
  bool operator==(const StatusPacket&) const = default;
};

/// One device's block in a Fast Sync Read / Fast Bulk Read reply.
struct FastReplyBlock {
  std::uint8_t error = 0;
  std::uint8_t id = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const FastReplyBlock&) const = default;
};

/// The single combined status packet (Packet ID 0xFE) that answers Fast Sync/Bulk Read, blocks
/// in request order (protocol2.md "Fast Sync Read (0x8A)").
struct FastReply {
  std::vector<FastReplyBlock> blocks;
  bool operator==(const FastReply&) const = default;
};

}  // namespace dxlemu::wire
