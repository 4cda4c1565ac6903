#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

// The layout of one fuzz input, shared by the fuzz targets (which parse it) and make_fuzz_corpus
// (which builds the seeds), so that both always agree:
//
//   byte 0              bits 0-3: number of leading chunks (0-15); bit 4: repair checks;
//                       bits 5-7: the target's own (the bus and Modbus targets: the line rate)
//   2 bytes per chunk   chunk length (0-255 bytes of the stream), time gap before the chunk
//   the rest            the byte stream; what the leading chunks leave over is fed as a last chunk
//
// A few control bytes give libFuzzer direct handles on the framer's inputs that a plain byte
// stream lacks: where the bytes are split between feed() calls and how much simulated time passes
// between them (inter-byte timeouts). Repairing checks lets mutations reach the decoders, which
// random bytes almost never do behind a CRC-16.
namespace dxlemu::fuzz {

/// Bits of byte 0 that hold the number of leading chunks.
inline constexpr std::uint8_t kChunkCountMask = 0x0F;
/// Most leading chunks an input can describe.
inline constexpr std::size_t kMaxChunks = kChunkCountMask;
/// Bit of byte 0 asking the target to rewrite the checksum/CRC of every complete packet in the
/// stream before feeding it.
inline constexpr std::uint8_t kRepairChecksFlag = 0x10;
/// Bits 5-7 of byte 0 (FuzzInput::spare) are left to each target.
inline constexpr unsigned kSpareShift = 5;
/// Bytes per chunk descriptor: length and gap.
inline constexpr std::size_t kChunkDescriptorBytes = 2;

/// Gap values are in units of 1/kGapUnitsPerTimeout of the protocol's inter-byte timeout, so that
/// gap kGapUnitsPerTimeout is exactly the timeout (still accepted) and the next value exceeds it.
inline constexpr std::uint8_t kGapUnitsPerTimeout = 128;
/// Gap value meaning "advance to the framer's deadline()", the first instant it drops a partial
/// packet (no advance when nothing is buffered).
inline constexpr std::uint8_t kGapToDeadline = 0xFF;
/// Gap value a silence-delimited target (Modbus RTU) reads as "the client's write ended before
/// this chunk" (Framer::end_of_write), with no time passing.
inline constexpr std::uint8_t kGapEndOfWrite = 0xFE;

/// One leading chunk: how many stream bytes it carries and the gap before it arrives.
struct Chunk {
  std::uint8_t length = 0;
  std::uint8_t gap = 0;
};

/// A parsed fuzz input. `stream` points into the caller's buffer.
struct FuzzInput {
  bool repair_checks = false;
  /// Bits 5-7 of byte 0, 0 ~ 7: the target's own choice.
  std::uint8_t spare = 0;
  std::vector<Chunk> chunks;
  std::span<const std::uint8_t> stream;
};

/// Splits raw fuzzer bytes into control part and stream. Never fails: a short input simply has
/// fewer chunks (or an empty stream).
inline FuzzInput parse_fuzz_input(std::span<const std::uint8_t> data) {
  FuzzInput input;
  if (data.empty()) {
    return input;
  }
  const std::uint8_t control = data[0];
  input.repair_checks = (control & kRepairChecksFlag) != 0;
  input.spare = static_cast<std::uint8_t>(control >> kSpareShift);
  const std::size_t count =
      std::min<std::size_t>(control & kChunkCountMask, (data.size() - 1) / kChunkDescriptorBytes);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t at = 1 + i * kChunkDescriptorBytes;
    input.chunks.push_back(Chunk{data[at], data[at + 1]});
  }
  input.stream = data.subspan(1 + count * kChunkDescriptorBytes);
  return input;
}

/// Builds the raw fuzzer bytes parse_fuzz_input() turns back into `chunks`, `repair_checks`,
/// `stream` and `spare`. Throws std::invalid_argument for more than kMaxChunks chunks or a
/// `spare` over 7.
inline std::vector<std::uint8_t> build_fuzz_input(std::span<const Chunk> chunks, bool repair_checks,
                                                  std::span<const std::uint8_t> stream,
                                                  std::uint8_t spare = 0) {
  if (chunks.size() > kMaxChunks) {
    throw std::invalid_argument("a fuzz input describes at most 15 chunks");
  }
  if (spare > (0xFFU >> kSpareShift)) {
    throw std::invalid_argument("a fuzz input's spare bits hold 0 ~ 7");
  }
  std::vector<std::uint8_t> out;
  out.push_back(static_cast<std::uint8_t>(chunks.size() | (repair_checks ? kRepairChecksFlag : 0) |
                                          (spare << kSpareShift)));
  for (const Chunk& chunk : chunks) {
    out.push_back(chunk.length);
    out.push_back(chunk.gap);
  }
  out.insert(out.end(), stream.begin(), stream.end());
  return out;
}

}  // namespace dxlemu::fuzz
