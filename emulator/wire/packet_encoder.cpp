#include "wire/packet_encoder.hpp"

#include <limits>
#include <stdexcept>
#include <string>

#include "wire/checksum.hpp"
#include "wire/crc16.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/stuffing.hpp"

namespace dxlemu::wire {
namespace {

constexpr std::uint8_t kHeaderByte = 0xFF;
constexpr std::uint8_t kV2HeaderByte3 = 0xFD;
constexpr std::size_t kFastBlockOverhead = 4;  // error, ID, CRC_L, CRC_H
// Header, ID and LENGTH, then the instruction byte.
constexpr std::size_t kFastHeadBytes = 8;
constexpr std::uint8_t kV2Reserved = 0x00;
constexpr std::size_t kV1LengthOverhead = 2;  // instruction + checksum
constexpr std::size_t kV2CrcBytes = 2;

void append_crc(std::vector<std::uint8_t>& packet, std::uint16_t crc) {
  packet.push_back(static_cast<std::uint8_t>(crc & 0xFFU));  // CRC_L first
  packet.push_back(static_cast<std::uint8_t>(crc >> 8));
}

std::vector<std::uint8_t> v2_head(std::uint8_t id, std::size_t length) {
  if (length > std::numeric_limits<std::uint16_t>::max()) {
    throw std::invalid_argument("Protocol 2.0 LENGTH " + std::to_string(length) +
                                " does not fit 16 bits");
  }
  return {kHeaderByte,
          kHeaderByte,
          kV2HeaderByte3,
          kV2Reserved,
          id,
          static_cast<std::uint8_t>(length & 0xFFU),
          static_cast<std::uint8_t>(length >> 8)};
}

}  // namespace

std::vector<std::uint8_t> encode_packet(Protocol protocol, std::uint8_t id,
                                        std::uint8_t instruction,
                                        std::span<const std::uint8_t> params) {
  if (has_v1_layout(protocol)) {
    const std::size_t length = params.size() + kV1LengthOverhead;
    if (length > std::numeric_limits<std::uint8_t>::max()) {
      throw std::invalid_argument(std::string(protocol_title(protocol)) + " LENGTH " +
                                  std::to_string(length) + " does not fit one byte");
    }
    std::vector<std::uint8_t> packet = {kHeaderByte, kHeaderByte, id,
                                        static_cast<std::uint8_t>(length), instruction};
    packet.insert(packet.end(), params.begin(), params.end());
    packet.push_back(v1_checksum(std::span(packet).subspan(2)));
    return packet;
  }
  // protocol2.md "Transmission Process": stuff, set LENGTH to the stuffed size, then the CRC.
  std::vector<std::uint8_t> region;
  region.reserve(params.size() + 1);
  region.push_back(instruction);
  region.insert(region.end(), params.begin(), params.end());
  const std::vector<std::uint8_t> stuffed = stuff(region);
  std::vector<std::uint8_t> packet = v2_head(id, stuffed.size() + kV2CrcBytes);
  packet.insert(packet.end(), stuffed.begin(), stuffed.end());
  append_crc(packet, crc16(packet));
  return packet;
}

std::vector<std::uint8_t> encode_status(const StatusPacket& status) {
  if (has_v1_layout(status.protocol)) {
    return encode_packet(status.protocol, status.id, status.error, status.params);
  }
  if (status.id == kBroadcastId) {
    // No device answers from the broadcast ID; a 2.0 status from 0xFE is a Fast reply, which is
    // laid out (and left unstuffed) differently: encode_fast_reply builds those.
    throw std::invalid_argument("a Protocol 2.0 status packet cannot come from ID 0xFE");
  }
  std::vector<std::uint8_t> params;
  params.reserve(status.params.size() + 1);
  params.push_back(status.error);
  params.insert(params.end(), status.params.begin(), status.params.end());
  return encode_packet(Protocol::V2, status.id, to_byte(InstructionCode::Status), params);
}

std::optional<std::uint16_t> fast_reply_length(std::span<const std::size_t> data_sizes) {
  // The instruction byte and the blocks; the packet's CRC is the last block's CRC.
  std::size_t length = 1;
  for (const std::size_t size : data_sizes) {
    length += kFastBlockOverhead + size;
    if (length > std::numeric_limits<std::uint16_t>::max()) {
      return std::nullopt;
    }
  }
  return static_cast<std::uint16_t>(length);
}

std::vector<std::uint8_t> encode_reply(const StatusPacket& status, const Answering& answering) {
  if (traits(status.protocol).status.shape == StatusShape::ExceptionCode) {
    return encode_modbus_response(status.id, answering.instruction, answering.request, status.error,
                                  status.params);
  }
  return encode_status(status);
}

std::vector<std::uint8_t> encode_fast_reply(const FastReply& reply) {
  std::size_t length = 1;
  for (const FastReplyBlock& block : reply.blocks) {
    length += kFastBlockOverhead + block.data.size();
  }
  std::vector<std::uint8_t> packet = v2_head(kBroadcastId, length);
  packet.push_back(to_byte(InstructionCode::Status));
  // One running CRC over the whole packet; each block ends with its value so far
  // (protocol2-crc.md "Fast Sync Read / Fast Bulk Read status packets").
  std::uint16_t crc = crc16(packet);
  for (const FastReplyBlock& block : reply.blocks) {
    const std::size_t from = packet.size();
    packet.push_back(block.error);
    packet.push_back(block.id);
    packet.insert(packet.end(), block.data.begin(), block.data.end());
    crc = crc16_update(crc, std::span(packet).subspan(from));
    append_crc(packet, crc);
    crc = crc16_update(crc, std::span(packet).last(kV2CrcBytes));
  }
  return packet;
}

std::vector<std::uint8_t> encode_fast_reply(const FastReply& reply, std::size_t blocks_sent) {
  std::vector<std::uint8_t> packet = encode_fast_reply(reply);
  std::size_t sent = kFastHeadBytes;
  for (std::size_t i = 0; i < blocks_sent && i < reply.blocks.size(); ++i) {
    sent += kFastBlockOverhead + reply.blocks[i].data.size();
  }
  packet.resize(sent);
  return packet;
}

}  // namespace dxlemu::wire
