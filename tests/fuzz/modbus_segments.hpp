#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "sim/sim_time.hpp"
#include "wire/crc16_modbus.hpp"
#include "wire/protocol.hpp"
#include "wire/rtu_timing.hpp"

// Where a Modbus RTU receiver cuts a byte stream into frames, worked out from the bytes' arrival
// times alone (modbus-rtu.md "RTU framing"), independently of wire::Framer: the fuzz targets
// compare the framer with it, and use it to repair the CRCs of the frames a stream will make
// before feeding it (random bytes almost never end in a valid CRC-16).
namespace dxlemu::fuzz {

/// The character times of Modbus RTU at one line rate, as the framer measures them.
struct ModbusLine {
  /// A byte's time on the line at `bps`: 10 bits (8N1), rounded up to the nanosecond; 0 at an
  /// unknown rate (0).
  sim::SimDuration byte_time{};
  /// The silence that ends a frame (t3.5) and the longest gap inside one (t1.5).
  sim::SimDuration silence{};
  sim::SimDuration gap{};

  static ModbusLine at(std::uint32_t bps) {
    constexpr std::int64_t kBitNanos = 10 * 1'000'000'000LL;  // 10 bits per byte, in ns
    const wire::FrameShape& shape = wire::traits(wire::Protocol::Modbus).frame;
    return ModbusLine{
        sim::SimDuration{bps == 0 ? 0 : (kBitNanos + bps - 1) / bps},
        wire::frame_silence(shape, bps),
        wire::frame_gap(shape, bps),
    };
  }
};

/// One run of bytes between two silences: what a receiver takes as one frame.
struct ModbusSegment {
  std::size_t begin = 0;  ///< index of its first byte in the stream
  std::size_t size = 0;
  bool broken = false;  ///< a gap over t1.5 fell inside it
  /// Arrival time of its first byte, and of the last byte the framer keeps (of a frame longer
  /// than the protocol allows it keeps max_length + 1 bytes).
  sim::SimTime first_at{};
  sim::SimTime last_kept_at{};
};

/// Follows a line byte by byte and cuts it where a receiver would: at a silence of at least t3.5
/// before a byte or when time reaches t3.5 after the last byte (advance), and where the client's
/// write ends when the line is taken to be silent after it (end_of_write).
class ModbusSegmenter {
 public:
  explicit ModbusSegmenter(const ModbusLine& line) : line_(line) {}

  /// When the open segment ends if no byte comes (t3.5 after its last byte); nullopt when none
  /// is open.
  std::optional<sim::SimTime> deadline() const {
    if (!open_) {
      return std::nullopt;
    }
    return last_end_ + line_.silence;
  }

  /// Time has reached `now`: the open segment ends if its silence has passed.
  void advance(sim::SimTime now) {
    if (open_ && now >= last_end_ + line_.silence) {
      close();
    }
  }

  /// The client's write ended and the line is taken to be silent.
  void end_of_write() { close(); }

  /// Byte `index` of the stream arrived at `at` (bytes come in order).
  void byte(std::size_t index, sim::SimTime at) {
    if (open_) {
      const sim::SimDuration quiet = at - last_end_;
      if (quiet >= line_.silence) {
        close();
      } else if (quiet > line_.gap) {
        current_.broken = true;
      }
    }
    if (!open_) {
      open_ = true;
      current_ = ModbusSegment{index, 0, false, at, at};
    }
    ++current_.size;
    if (current_.size <= kKeptBytes) {
      current_.last_kept_at = at;
    }
    last_end_ = at + line_.byte_time;
  }

  /// Ends the open segment, if any.
  void close() {
    if (open_) {
      segments_.push_back(current_);
      open_ = false;
    }
  }

  /// The segments ended so far, in stream order.
  const std::vector<ModbusSegment>& segments() const { return segments_; }

  /// Bytes of an overlong frame the framer keeps (Framer::feed_silent: up to max_length + 1).
  static constexpr std::size_t kKeptBytes =
      std::size_t{wire::traits(wire::Protocol::Modbus).frame.max_length} + 1;

 private:
  ModbusLine line_;
  bool open_ = false;
  ModbusSegment current_;
  sim::SimTime last_end_{};
  std::vector<ModbusSegment> segments_;
};

/// True when `segment` is a frame the framer yields once its CRC is right: unbroken and of a
/// size the protocol allows.
inline bool modbus_frame_size(const ModbusSegment& segment) {
  const wire::FrameShape& shape = wire::traits(wire::Protocol::Modbus).frame;
  return !segment.broken && segment.size >= shape.min_length && segment.size <= shape.max_length;
}

/// Rewrites the last two bytes of every segment that can be a frame with the CRC of the bytes
/// before them (low byte first).
inline void repair_modbus_crcs(std::vector<std::uint8_t>& stream,
                               std::span<const ModbusSegment> segments) {
  constexpr std::size_t kCrcBytes = 2;
  for (const ModbusSegment& s : segments) {
    if (!modbus_frame_size(s) || s.begin + s.size > stream.size()) {
      continue;
    }
    const std::span<std::uint8_t> frame = std::span(stream).subspan(s.begin, s.size);
    const std::uint16_t crc = wire::crc16_modbus(frame.first(s.size - kCrcBytes));
    frame[s.size - 2] = static_cast<std::uint8_t>(crc & 0xFFU);
    frame[s.size - 1] = static_cast<std::uint8_t>(crc >> 8);
  }
}

}  // namespace dxlemu::fuzz
