#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "wire/checksum.hpp"
#include "wire/crc16.hpp"
#include "wire/framer.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::fuzz {

namespace detail {

// The packet of `format` starting at `i`, if its header is there and its LENGTH is plausible and
// fits in `stream`; returns its total size, else 0.
inline std::size_t packet_at(const std::vector<std::uint8_t>& stream, std::size_t i,
                             const wire::FrameFormat& format) {
  const std::size_t h = format.header.size();
  const std::size_t prefix = h + 1 + format.length_field_bytes;  // header, ID, LENGTH
  if (i + prefix > stream.size() || !std::equal(format.header.begin(), format.header.end(),
                                                stream.begin() + static_cast<std::ptrdiff_t>(i))) {
    return 0;
  }
  std::size_t length = stream[i + h + 1];
  if (format.length_field_bytes == 2) {
    length |= static_cast<std::size_t>(stream[i + h + 2]) << 8;
  }
  const std::size_t total = prefix + length;
  if (length < format.min_length || length > format.max_length || i + total > stream.size()) {
    return 0;
  }
  return total;
}

inline void repair_packet(std::span<std::uint8_t> packet, const wire::FrameFormat& format) {
  const std::size_t total = packet.size();
  if (wire::has_v1_layout(format.protocol)) {
    // The checksum covers ID .. last parameter (protocol1.md "Checksum", FEETECH alike).
    const std::size_t h = format.header.size();
    packet[total - 1] = wire::v1_checksum(packet.subspan(h, total - h - 1));
  } else {
    // The CRC covers header .. last parameter and is sent low byte first.
    const std::uint16_t crc = wire::crc16(packet.first(total - 2));
    packet[total - 2] = static_cast<std::uint8_t>(crc & 0xFFU);
    packet[total - 1] = static_cast<std::uint8_t>(crc >> 8);
  }
}

}  // namespace detail

/// Rewrites the checksum (1.0, FEETECH) or CRC (2.0) of every complete packet of `protocols` in
/// `stream`, walking it as a receiver would: a header with a plausible LENGTH that fits is a
/// packet, anything else is stepped over byte by byte. Where both protocols are given, a 2.0 header
/// is tried first (FF FF FD 00 also starts like a 1.0 packet). Random bytes almost never pass a
/// CRC-16: this lets mutations reach the decoders and the servos.
inline void repair_checks(std::vector<std::uint8_t>& stream,
                          std::span<const wire::Protocol> protocols) {
  std::vector<wire::FrameFormat> formats;
  for (const wire::Protocol p : protocols) {
    formats.push_back(wire::FrameFormat::for_protocol(p));
  }
  std::sort(formats.begin(), formats.end(),
            [](const auto& a, const auto& b) { return a.header.size() > b.header.size(); });
  std::size_t i = 0;
  while (i < stream.size()) {
    std::size_t total = 0;
    for (const wire::FrameFormat& format : formats) {
      total = detail::packet_at(stream, i, format);
      if (total > 0) {
        detail::repair_packet(std::span(stream).subspan(i, total), format);
        break;
      }
    }
    i += total > 0 ? total : 1;
  }
}

}  // namespace dxlemu::fuzz
