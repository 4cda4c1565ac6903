#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <variant>

#include "wire/frame.hpp"
#include "wire/instruction.hpp"
#include "wire/status.hpp"

namespace dxlemu::wire {

/// Which kind of rule a packet broke. A servo (`model::Servo::refuse`) answers BadValue with
/// Data Range Error and BadLength with Data Length Error (Protocol 1.0: the Range Error bit and
/// the Instruction Error bit).
enum class DecodeErrorKind {
  BadLength,   ///< The parameter bytes do not fit the instruction's layout.
  BadValue,    ///< A field holds a value the instruction does not allow.
  BadAddress,  ///< An address no device has (a Modbus register beyond any control table).
  NotStatus,   ///< Expected a status packet, got something else.
};

/// Why a verified frame could not be decoded. Never thrown: returned.
struct DecodeError {
  DecodeErrorKind kind = DecodeErrorKind::BadLength;
  std::uint8_t id = 0;
  std::uint8_t instruction = 0;
  /// Which rule failed, e.g. "read needs 4 parameter bytes (address, length), got 3".
  std::string reason;
  bool operator==(const DecodeError&) const = default;
};

/// The decoded value or why there is none.
template <class T>
using DecodeResult = std::variant<T, DecodeError>;

/// Decodes an instruction packet of the frame's protocol. Instructions the protocol does not
/// define decode as UnknownInstruction (a servo answers them with Instruction Error); parameter
/// layouts are validated (lengths, block sizes, fixed bytes, option values).
DecodeResult<InstructionPacket> decode_instruction(const Frame& frame);

/// Decodes a status packet (2.0: instruction 0x55 and an error byte; 1.0 and FEETECH: any packet,
/// the instruction position holding the error).
DecodeResult<StatusPacket> decode_status(const Frame& frame);

/// Decodes a Fast Sync/Bulk Read reply; `lengths` are the data lengths requested of each device,
/// in request order. Every embedded CRC is checked against the running CRC of the packet.
DecodeResult<FastReply> decode_fast_reply(const Frame& frame,
                                          std::span<const std::uint16_t> lengths);

}  // namespace dxlemu::wire
