#include "wire/framer.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "wire/checksum.hpp"
#include "wire/crc16.hpp"
#include "wire/rtu_timing.hpp"
#include "wire/stuffing.hpp"

namespace dxlemu::wire {
namespace {

using sim::SimDuration;

constexpr std::uint8_t kV2HeaderThirdByte = 0xFD;  // read as a 1.0 ID by the 1.0 framer

// Compaction threshold: resolved bytes are erased from the front of the buffer in batches.
constexpr std::size_t kCompactBytes = 4096;

}  // namespace

FrameFormat FrameFormat::for_protocol(Protocol protocol) {
  const FrameShape& shape = traits(protocol).frame;
  FrameFormat f;
  f.protocol = protocol;
  f.silence_delimited = shape.delimiting == Delimiting::Silence;
  f.header.assign(shape.header.begin(), shape.header.begin() + shape.header_size);
  f.length_field_bytes = shape.field_bytes;
  f.min_length = shape.min_length;
  f.max_length = shape.max_length;
  f.check_bytes = shape.check == CheckKind::Sum8 ? 1 : 2;
  f.inter_byte_timeout = shape.inter_byte_timeout;
  return f;
}

Framer::Framer(Protocol protocol) : Framer(FrameFormat::for_protocol(protocol)) {}

Framer::Framer(FrameFormat format) : format_(std::move(format)) {}

void Framer::feed(std::span<const std::uint8_t> bytes, sim::SimTime at,
                  std::vector<FramerEvent>& out) {
  expire(at, out);  // even when nothing came: time passed
  const std::vector<sim::SimTime> times(bytes.size(), at);
  feed(bytes, times, out);
}

void Framer::feed(std::span<const std::uint8_t> bytes, std::span<const sim::SimTime> times,
                  std::vector<FramerEvent>& out) {
  if (times.size() != bytes.size()) {
    throw std::invalid_argument("Framer::feed: one arrival time per byte");
  }
  if (bytes.empty()) {
    return;
  }
  if (format_.silence_delimited) {
    feed_silent(bytes, times, out);
    return;
  }
  expire(times.front(), out);
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
  times_.insert(times_.end(), times.begin(), times.end());
  last_at_ = times.back();
  scan(false, out);
}

void Framer::expire(sim::SimTime now, std::vector<FramerEvent>& out) {
  if (format_.silence_delimited) {
    if (const auto due = deadline(); due && now >= *due) {
      close_silent(out);
    }
    return;
  }
  // "If the delay time is over 1.5ms": a gap exactly equal to the timeout is still accepted.
  if (buffered() > 0 && now - last_at_ > format_.inter_byte_timeout) {
    scan(true, out);
  }
}

std::optional<sim::SimTime> Framer::deadline() const {
  if (buffered() == 0 && overflow_ == 0) {
    return std::nullopt;
  }
  if (format_.silence_delimited) {
    // "At least 3.5 character times": a silence exactly that long ends the frame.
    return last_end_ + frame_silence(traits(format_.protocol).frame, bps_);
  }
  return last_at_ + format_.inter_byte_timeout + SimDuration{1};
}

std::size_t Framer::find_header(std::size_t from) const {
  const std::size_t h = format_.header.size();
  for (std::size_t i = from; i < buf_.size(); ++i) {
    const std::size_t n = std::min(h, buf_.size() - i);
    if (std::equal(format_.header.begin(), format_.header.begin() + static_cast<std::ptrdiff_t>(n),
                   buf_.begin() + static_cast<std::ptrdiff_t>(i))) {
      return i;  // a full header, or a prefix of one that runs to the end of the buffer
    }
  }
  return buf_.size();
}

bool Framer::check_ok(std::size_t pos, std::size_t total) const {
  const std::span<const std::uint8_t> packet(buf_.data() + pos, total);
  if (has_v1_layout(format_.protocol)) {
    // The checksum covers ID .. last parameter: everything after the header, before the checksum.
    const std::size_t h = format_.header.size();
    return v1_checksum(packet.subspan(h, total - h - 1)) == packet[total - 1];
  }
  // The CRC covers header .. last parameter, stuffing included; it is sent low byte first.
  const std::uint16_t crc = crc16(packet.first(total - 2));
  return packet[total - 2] == (crc & 0xFFU) && packet[total - 1] == (crc >> 8);
}

Frame Framer::make_frame(std::size_t pos, std::size_t total) const {
  const std::size_t body = pos + format_.header.size() + 1 + format_.length_field_bytes;
  const auto first = buf_.begin() + static_cast<std::ptrdiff_t>(pos);
  Frame frame;
  frame.protocol = format_.protocol;
  frame.id = buf_[pos + format_.header.size()];
  frame.raw.assign(first, first + static_cast<std::ptrdiff_t>(total));
  frame.first_byte_at = times_[pos];
  frame.last_byte_at = times_[pos + total - 1];
  frame.offset = dropped_ + pos;
  // Instruction and parameters: everything between LENGTH and the check bytes.
  const std::span<const std::uint8_t> region(buf_.data() + body,
                                             pos + total - format_.check_bytes - body);
  frame.instruction = region.front();
  // protocol2.md "Processing Order of Reception": remove stuffing once the CRC matched, over the
  // same region the sender stuffed (instruction byte included, as the DynamixelSDK does). Fast
  // Sync/Bulk Read replies (ID 0xFE, instruction 0x55) are sent unstuffed and stay as sent.
  if (format_.protocol == Protocol::V2 &&
      !is_fast_reply(format_.protocol, frame.id, frame.instruction)) {
    const std::vector<std::uint8_t> plain = unstuff(region);
    frame.params.assign(plain.begin() + 1, plain.end());
  } else {
    frame.params.assign(region.begin() + 1, region.end());
  }
  return frame;
}

void Framer::skip_garbage(std::size_t count) {
  for (std::size_t i = start_; i < start_ + count; ++i) {
    if (i < quiet_end_) {
      continue;  // part of a packet an error already reported
    }
    if (garbage_count_ == 0) {
      garbage_at_ = times_[i];
      garbage_offset_ = dropped_ + i;
    }
    ++garbage_count_;
  }
  start_ += count;
}

void Framer::flush_garbage(std::vector<FramerEvent>& out) {
  if (garbage_count_ == 0) {
    return;
  }
  FramingError e;
  e.kind = FramingErrorKind::Garbage;
  e.protocol = format_.protocol;
  e.bytes = garbage_count_;
  e.at = garbage_at_;
  e.offset = garbage_offset_;
  // A run is contiguous (an error or a frame flushes it) and every scan flushes before compact(),
  // so its bytes are still in buf_; one copy per run, however long, never per byte.
  const auto first = buf_.begin() + static_cast<std::ptrdiff_t>(garbage_offset_ - dropped_);
  e.raw.assign(first, first + static_cast<std::ptrdiff_t>(garbage_count_));
  out.emplace_back(std::move(e));
  garbage_count_ = 0;
}

void Framer::reject(FramingErrorKind kind, std::size_t pos, std::size_t bytes,
                    std::vector<FramerEvent>& out) {
  flush_garbage(out);
  const std::size_t h = format_.header.size();
  FramingError e;
  e.kind = kind;
  e.protocol = format_.protocol;
  e.bytes = bytes;
  e.at = times_[pos];
  e.offset = dropped_ + pos;
  if (pos + h < buf_.size()) {
    e.id = buf_[pos + h];
  }
  const std::size_t instruction_at = pos + h + 1 + format_.length_field_bytes;
  if (instruction_at < pos + bytes) {
    e.instruction = buf_[instruction_at];
  }
  const auto first = buf_.begin() + static_cast<std::ptrdiff_t>(pos);
  e.raw.assign(first, first + static_cast<std::ptrdiff_t>(bytes));
  out.emplace_back(std::move(e));
  // Rescan from the byte after the failed header's first byte; the rejected bytes are not
  // reported a second time as garbage, but a packet starting inside them is still found.
  quiet_end_ = std::max(quiet_end_, pos + bytes);
  start_ = pos + 1;
}

void Framer::scan(bool stale, std::vector<FramerEvent>& out) {
  const std::size_t h = format_.header.size();
  const std::size_t prefix = h + 1 + format_.length_field_bytes;  // header, ID, LENGTH
  while (start_ < buf_.size()) {
    const std::size_t pos = find_header(start_);
    skip_garbage(pos - start_);
    const std::size_t avail = buf_.size() - pos;
    if (avail == 0) {
      break;
    }
    if (avail < h) {  // a header prefix at the end of the buffer
      if (!stale) {
        break;
      }
      skip_garbage(avail);
      break;
    }
    if (avail < prefix) {
      if (!stale) {
        break;
      }
      reject(FramingErrorKind::Truncated, pos, avail, out);
      continue;
    }
    const std::uint8_t id = buf_[pos + h];
    if (!is_valid_packet_id(format_.protocol, id)) {
      skip_garbage(1);  // not a header after all
      continue;
    }
    std::size_t length = buf_[pos + h + 1];
    // FF FF FD 00 is the Protocol 2.0 header: on a mixed bus it is the other protocol's traffic,
    // not a broken 1.0 packet (whose LENGTH is never 0), so it is skipped like any other noise.
    // No DYNAMIXEL 2.0 device shares a bus with FEETECH servos, so there it is what it reads as:
    // a packet to ID 0xFD with an impossible LENGTH.
    if (format_.protocol == Protocol::V1 && id == kV2HeaderThirdByte && length == 0) {
      skip_garbage(1);
      continue;
    }
    if (format_.length_field_bytes == 2) {
      length |= static_cast<std::size_t>(buf_[pos + h + 2]) << 8;
    }
    if (length < format_.min_length || length > format_.max_length) {
      reject(FramingErrorKind::ImpossibleLength, pos, prefix, out);
      continue;
    }
    const std::size_t total = prefix + length;
    if (avail < total) {
      if (!stale) {
        break;
      }
      reject(FramingErrorKind::Truncated, pos, avail, out);
      continue;
    }
    if (!check_ok(pos, total)) {
      reject(FramingErrorKind::BadCheck, pos, total, out);
      continue;
    }
    flush_garbage(out);
    out.emplace_back(make_frame(pos, total));
    start_ = pos + total;
  }
  flush_garbage(out);
  compact();
}

void Framer::compact() {
  if (start_ >= buf_.size()) {
    dropped_ += buf_.size();
    buf_.clear();
    times_.clear();
    start_ = 0;
    quiet_end_ = 0;
    return;
  }
  if (start_ < kCompactBytes && start_ * 2 < buf_.size()) {
    return;
  }
  const auto n = static_cast<std::ptrdiff_t>(start_);
  dropped_ += start_;
  buf_.erase(buf_.begin(), buf_.begin() + n);
  times_.erase(times_.begin(), times_.begin() + n);
  quiet_end_ = quiet_end_ > start_ ? quiet_end_ - start_ : 0;
  start_ = 0;
}

}  // namespace dxlemu::wire
