#pragma once

#include <cstdint>

namespace dxlemu::bus {

/// Counters of one bus, for the control API's `stats` and for tests.
struct BusStats {
  std::uint64_t bytes_in = 0;       ///< bytes the client wrote
  std::uint64_t frames = 0;         ///< instruction packets with a valid header and check
  std::uint64_t garbage_bytes = 0;  ///< bytes skipped while looking for a header
  std::uint64_t bad_checks = 0;     ///< packets with a wrong CRC or checksum
  std::uint64_t truncated = 0;      ///< partial packets dropped after the inter-byte timeout
  std::uint64_t impossible_lengths = 0;
  std::uint64_t decode_errors = 0;    ///< frames whose parameters broke the instruction's layout
  std::uint64_t replies = 0;          ///< status packets handed to the link
  std::uint64_t unread_drops = 0;     ///< packets the link dropped: the client was not reading
  std::uint64_t collisions = 0;       ///< instructions that arrived while replies were still due
  std::uint64_t id_conflicts = 0;     ///< replies garbled because two servos share an ID
  std::uint64_t faults_injected = 0;  ///< packets a fault rule acted on (docs/faults.md)
};

}  // namespace dxlemu::bus
