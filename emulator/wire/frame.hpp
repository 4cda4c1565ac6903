#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "sim/sim_time.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::wire {

/// One packet whose header, length and CRC/checksum were verified by a Framer. It is not yet
/// interpreted: decode_instruction / decode_status turn it into fields.
struct Frame {
  Protocol protocol = Protocol::V2;
  std::uint8_t id = 0;
  /// The instruction byte; in a Protocol 1.0 status packet this position holds the error byte,
  /// in a Protocol 2.0 status packet it is 0x55 and the error byte is params[0].
  std::uint8_t instruction = 0;
  /// Everything between the instruction byte and the CRC/checksum, with byte stuffing removed
  /// (except in Fast Sync/Bulk Read replies, which are never stuffed).
  std::vector<std::uint8_t> params;
  /// The packet as it was on the wire, header to CRC/checksum.
  std::vector<std::uint8_t> raw;
  /// Arrival times (simulated clock) of the packet's first and last byte.
  sim::SimTime first_byte_at{};
  sim::SimTime last_byte_at{};
  /// Position of the first byte among all the bytes fed to the framer (0: the very first).
  std::uint64_t offset = 0;

  bool operator==(const Frame&) const = default;
};

/// What went wrong while framing.
enum class FramingErrorKind {
  Garbage,           ///< Bytes that do not start a packet, skipped while searching for a header.
  BadCheck,          ///< Complete packet whose CRC (2.0) or checksum (1.0) does not match.
  ImpossibleLength,  ///< Header with a LENGTH no packet can have.
  Truncated,         ///< Partial packet dropped after the inter-byte timeout.
};

/// A framing failure. The framer has already resynchronised after it; nothing is to be undone.
struct FramingError {
  FramingErrorKind kind = FramingErrorKind::Garbage;
  Protocol protocol = Protocol::V2;
  /// Bytes the error covers (for BadCheck the whole packet, for Truncated the partial packet).
  std::size_t bytes = 0;
  /// The Packet ID read from the header, unverified (a servo may answer a CRC error with it).
  std::optional<std::uint8_t> id;
  /// The instruction byte, unverified, when the header got that far.
  std::optional<std::uint8_t> instruction;
  /// Arrival time of the first byte concerned.
  sim::SimTime at{};
  /// Position of the first byte concerned among all the bytes fed to the framer.
  std::uint64_t offset = 0;
  /// The bytes concerned as they were on the wire (`bytes` of them, from `offset` on): the skipped
  /// run for Garbage, header, ID and LENGTH for ImpossibleLength, the whole packet for BadCheck,
  /// the partial packet for Truncated. Last, so that initialisations listing the fields above in
  /// order still compile; empty in an error made outside a Framer.
  std::vector<std::uint8_t> raw{};

  bool operator==(const FramingError&) const = default;
};

/// One output of a Framer, in the order the bytes arrived.
using FramerEvent = std::variant<Frame, FramingError>;

/// True for the header of a Fast Sync/Bulk Read reply: Protocol 2.0, ID 0xFE, instruction 0x55
/// (protocol2.md "Fast Sync Read (0x8A)"). It is never stuffed, and only the request knows its
/// blocks' lengths.
inline bool is_fast_reply(Protocol protocol, std::uint8_t id, std::uint8_t instruction) {
  return protocol == Protocol::V2 && id == kBroadcastId &&
         instruction == to_byte(InstructionCode::Status);
}

/// Position of the first byte an event covers among all the bytes fed to its framer.
inline std::uint64_t offset_of(const FramerEvent& event) {
  const auto* frame = std::get_if<Frame>(&event);
  return frame != nullptr ? frame->offset : std::get<FramingError>(event).offset;
}

}  // namespace dxlemu::wire
