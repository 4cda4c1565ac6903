#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "wire/instruction.hpp"
#include "wire/protocol.hpp"
#include "wire/status.hpp"

namespace dxlemu::wire {

/// Builds a complete packet: header, ID, LENGTH, `instruction`, `params`, checksum (1.0, FEETECH)
/// or stuffing and CRC (2.0). Throws std::invalid_argument when the packet cannot be expressed
/// (1.0 or FEETECH LENGTH over 255, 2.0 LENGTH over 65535): a caller bug, never a reaction to
/// input.
std::vector<std::uint8_t> encode_packet(Protocol protocol, std::uint8_t id,
                                        std::uint8_t instruction,
                                        std::span<const std::uint8_t> params);

/// Builds a status packet (2.0: instruction 0x55 followed by the error byte; 1.0 and FEETECH: the
/// error byte in the instruction position). Throws
/// std::invalid_argument for a 2.0 status from ID 0xFE: only a Fast reply comes from there.
std::vector<std::uint8_t> encode_status(const StatusPacket& status);

/// What a reply answers: the request's instruction byte and, when it could be decoded, the
/// request. Modbus RTU responses need both (the function code, the echo of a write); the
/// DYNAMIXEL and FEETECH status packets neither.
struct Answering {
  std::uint8_t instruction = 0;
  const Instruction* request = nullptr;
};

/// Builds the reply `status` stands for, answering `answering`: a status packet (encode_status),
/// or in Modbus RTU the response to the function answered, an exception response when
/// `status.error` holds an exception code (`status.params`: the control-table bytes a register
/// read read).
std::vector<std::uint8_t> encode_reply(const StatusPacket& status, const Answering& answering);

/// Builds the combined Fast Sync/Bulk Read reply: Packet ID 0xFE, each block followed by the
/// running CRC of the packet so far, the last one being the packet's CRC; never stuffed.
std::vector<std::uint8_t> encode_fast_reply(const FastReply& reply);

/// The Fast reply `reply` as it reaches the client when only its first `blocks_sent` devices
/// answered (the chain broke after them): LENGTH still announces every block, and the bytes stop
/// after the last block sent.
std::vector<std::uint8_t> encode_fast_reply(const FastReply& reply, std::size_t blocks_sent);

/// The LENGTH a Fast reply announces for blocks carrying `data_sizes` bytes each, or nullopt when
/// that does not fit its 16 bits (then no device can send the reply).
std::optional<std::uint16_t> fast_reply_length(std::span<const std::size_t> data_sizes);

}  // namespace dxlemu::wire
