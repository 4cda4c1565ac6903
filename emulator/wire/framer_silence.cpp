// Framing by silence (Modbus RTU, modbus-rtu.md "RTU framing"): no header and no LENGTH; a frame
// is every byte between two silences of at least t3.5, and a gap over t1.5 inside it makes it
// incomplete, so the receiver discards it. The framer keeps one frame at a time.
#include <algorithm>

#include "wire/crc16_modbus.hpp"
#include "wire/framer.hpp"
#include "wire/rtu_timing.hpp"

namespace dxlemu::wire {
namespace {

constexpr std::int64_t kBitsPerByte = 10;  // the line is 8N1: start, 8 data bits, stop
constexpr std::int64_t kNanosPerSecond = 1'000'000'000;
constexpr std::size_t kCrcBytes = 2;

}  // namespace

sim::SimDuration Framer::byte_time() const {
  if (bps_ == 0) {
    return sim::SimDuration{0};
  }
  return sim::SimDuration{(kBitsPerByte * kNanosPerSecond + bps_ - 1) / bps_};
}

void Framer::feed_silent(std::span<const std::uint8_t> bytes, std::span<const sim::SimTime> times,
                         std::vector<FramerEvent>& out) {
  const FrameShape& shape = traits(format_.protocol).frame;
  const sim::SimDuration silence = frame_silence(shape, bps_);
  const sim::SimDuration gap = frame_gap(shape, bps_);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const sim::SimTime at = times[i];
    if (!buf_.empty() || overflow_ > 0) {
      const sim::SimDuration quiet = at - last_end_;
      if (quiet >= silence) {
        close_silent(out);
      } else if (quiet > gap) {
        broken_ = true;  // "the message frame is declared incomplete"
      }
    }
    // A frame longer than the protocol allows is kept only as far as its limit: the rest is
    // counted, so that a stream without silences cannot grow the buffer.
    if (buf_.size() <= format_.max_length) {
      buf_.push_back(bytes[i]);
      times_.push_back(at);
    } else {
      ++overflow_;
    }
    last_end_ = at + byte_time();
    last_at_ = at;
  }
}

void Framer::end_of_write(std::vector<FramerEvent>& out) {
  if (format_.silence_delimited && (!buf_.empty() || overflow_ > 0)) {
    close_silent(out);
  }
}

void Framer::close_silent(std::vector<FramerEvent>& out) {
  const std::size_t size = buf_.size();
  const std::uint64_t total = size + overflow_;
  const auto fail = [&](FramingErrorKind kind) {
    FramingError e;
    e.kind = kind;
    e.protocol = format_.protocol;
    e.bytes = total;
    e.at = times_.front();
    e.offset = dropped_;
    e.id = buf_[0];
    if (size > 1) {
      e.instruction = buf_[1];
    }
    e.raw = buf_;
    out.emplace_back(std::move(e));
  };
  if (broken_ || total < format_.min_length) {
    fail(FramingErrorKind::Truncated);
  } else if (total > format_.max_length) {
    fail(FramingErrorKind::ImpossibleLength);
  } else {
    const std::uint16_t crc = crc16_modbus(std::span(buf_).first(size - kCrcBytes));
    if (buf_[size - 2] != (crc & 0xFFU) || buf_[size - 1] != (crc >> 8)) {
      fail(FramingErrorKind::BadCheck);
    } else {
      Frame frame;
      frame.protocol = format_.protocol;
      frame.id = buf_[0];
      frame.instruction = buf_[1];
      frame.params.assign(buf_.begin() + 2, buf_.end() - kCrcBytes);
      frame.raw = buf_;
      frame.first_byte_at = times_.front();
      frame.last_byte_at = times_.back();
      frame.offset = dropped_;
      out.emplace_back(std::move(frame));
    }
  }
  dropped_ += total;
  buf_.clear();
  times_.clear();
  broken_ = false;
  overflow_ = 0;
}

}  // namespace dxlemu::wire
