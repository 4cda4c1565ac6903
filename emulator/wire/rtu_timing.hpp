#pragma once

// The silences of a silence-delimited protocol (Modbus RTU), from its row's FrameShape.

#include <cstdint>

#include "sim/sim_time.hpp"
#include "wire/protocol_table.hpp"

namespace dxlemu::wire {

/// `tenths` tenths of a character time at `bps`, by the shape's rule: `char_bits` bits per
/// character, or the fixed time above `fixed_timing_above_bps` (and at an unknown rate, 0).
constexpr sim::SimDuration character_tenths(const FrameShape& shape, std::uint32_t bps,
                                            std::uint8_t tenths, sim::SimDuration fixed) {
  if (bps == 0 || (shape.fixed_timing_above_bps != 0 && bps > shape.fixed_timing_above_bps)) {
    return fixed;
  }
  constexpr std::int64_t kNanosPerSecond = 1'000'000'000;
  constexpr std::int64_t kTenths = 10;
  const std::int64_t bits_x10 = std::int64_t{tenths} * shape.char_bits;
  const std::int64_t denominator = kTenths * bps;
  return sim::SimDuration{(bits_x10 * kNanosPerSecond + denominator - 1) / denominator};
}

/// The silence that ends a frame at `bps` (Modbus RTU: t3.5; 1,750 us above 19,200 bit/s).
constexpr sim::SimDuration frame_silence(const FrameShape& shape, std::uint32_t bps) {
  return character_tenths(shape, bps, shape.silence_tenths, shape.fixed_silence);
}

/// The longest gap a frame survives at `bps` (Modbus RTU: t1.5; 750 us above 19,200 bit/s).
constexpr sim::SimDuration frame_gap(const FrameShape& shape, std::uint32_t bps) {
  return character_tenths(shape, bps, shape.gap_tenths, shape.fixed_gap);
}

}  // namespace dxlemu::wire
