// Writes the seed corpus of one fuzz target: every golden packet of the protocol as its own input,
// plus a few combined inputs that start the fuzzer off with several packets per stream, garbage
// between them, split chunks and inter-byte timeouts. The corpus is derived at build time from
// tests/data/golden_packets.txt (DYNAMIXEL), FEETECH's example frames (feetech_examples.cpp) or
// Modbus RTU's frames (modbus_seed_frames.cpp) and never committed. Modbus RTU frames end at a
// silence rather than a LENGTH, so its combined seeds put silences between frames (chunk gaps,
// fuzz_wire_modbus.cpp) and cut frames at t1.5 and t3.5.
//
// Usage: make_fuzz_corpus <1|2|feetech|modbus> <golden_packets.txt> <output directory>

#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "feetech_examples.hpp"
#include "fuzz_input.hpp"
#include "golden_file.hpp"
#include "modbus_seed_frames.hpp"

namespace {

namespace fs = std::filesystem;
using dxlemu::fuzz::Chunk;

// Noise put between packets in the garbage seed: a lone zero, stray 0xFF bytes that look like
// the start of a header, and FF FF FD 00 FF (to 2.0 a header with an invalid ID, to 1.0 one with
// an impossible LENGTH), so that resynchronisation after each kind is in the corpus from the start.
const std::vector<std::vector<std::uint8_t>> kGarbage = {
    {0x00}, {0xFF}, {0xFF, 0xFF, 0xFF}, {0x55, 0xAA}, {0xFF, 0xFF, 0xFD, 0x00, 0xFF},
};

// Cuts of the timeout seed: a few bytes, then the rest after a gap of exactly the timeout
// (still one packet), after a gap just over it (the partial packet is dropped) and at the
// framer's deadline.
constexpr std::uint8_t kShortChunk = 3;
constexpr std::uint8_t kLongChunk = 255;
constexpr std::array<Chunk, 6> kTimeoutChunks = {{
    {kShortChunk, 0},
    {kLongChunk, dxlemu::fuzz::kGapUnitsPerTimeout},
    {kShortChunk, 0},
    {kLongChunk, dxlemu::fuzz::kGapUnitsPerTimeout + 1},
    {kShortChunk, 0},
    {kLongChunk, dxlemu::fuzz::kGapToDeadline},
}};

void write_seed(const fs::path& dir, const std::string& name, std::span<const Chunk> chunks,
                bool repair_checks, std::span<const std::uint8_t> stream, std::uint8_t spare = 0) {
  const std::vector<std::uint8_t> input =
      dxlemu::fuzz::build_fuzz_input(chunks, repair_checks, stream, spare);
  std::ofstream out(dir / name, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(input.data()),
            static_cast<std::streamsize>(input.size()));
  if (!out) {
    throw std::runtime_error((dir / name).string() + ": cannot write");
  }
}

void append(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes) {
  out.insert(out.end(), bytes.begin(), bytes.end());
}

// One seed packet: a file name and the bytes, and the page's misprint of them if it has one.
struct Seed {
  std::string name;
  std::vector<std::uint8_t> bytes;
  std::optional<std::vector<std::uint8_t>> printed;
};

std::vector<Seed> golden_seeds(dxlemu::wire::Protocol protocol, const std::string& golden_path) {
  std::vector<Seed> seeds;
  for (const auto& packet : dxlemu::test::load_golden_packets(golden_path)) {
    if (packet.protocol == protocol) {
      seeds.push_back({packet.name, packet.bytes, packet.printed});
    }
  }
  return seeds;
}

// FEETECH's examples have no names: "feetech.<n>" in page order.
std::vector<Seed> feetech_seeds() {
  std::vector<Seed> seeds;
  for (const auto& example : dxlemu::test::feetech_examples()) {
    seeds.push_back({"feetech." + std::to_string(seeds.size() + 1), example.bytes, std::nullopt});
  }
  return seeds;
}

void make_corpus(const std::vector<Seed>& seeds, const fs::path& dir) {
  fs::create_directories(dir);
  std::vector<std::uint8_t> all;
  std::vector<std::uint8_t> with_garbage;
  std::vector<std::uint8_t> broken_checks;
  std::size_t count = 0;
  for (const Seed& packet : seeds) {
    write_seed(dir, packet.name, {}, false, packet.bytes);
    if (packet.printed) {
      // The page's misprint fails the check: a ready-made BadCheck input.
      write_seed(dir, packet.name + ".printed", {}, false, *packet.printed);
    }
    append(all, packet.bytes);
    append(with_garbage, kGarbage[count % kGarbage.size()]);
    append(with_garbage, packet.bytes);
    // The last byte of a packet is always check (checksum or CRC_H); the repair flag fixes it.
    append(broken_checks, packet.bytes);
    broken_checks.back() ^= 0xFFU;
    ++count;
  }
  if (count == 0) {
    throw std::runtime_error("no seed packets of this protocol");
  }

  std::vector<Chunk> split;
  for (std::uint8_t length = 1; split.size() < dxlemu::fuzz::kMaxChunks; ++length) {
    split.push_back(Chunk{length, 0});
  }
  write_seed(dir, "all_packets", {}, false, all);
  write_seed(dir, "all_packets_split", split, false, all);
  write_seed(dir, "all_packets_timeouts", kTimeoutChunks, false, all);
  write_seed(dir, "all_packets_with_garbage", {}, false, with_garbage);
  write_seed(dir, "all_packets_repaired", {}, true, broken_checks);
}

// Modbus RTU: every frame alone, then streams of them between silences (one chunk per frame, at
// most 15 a seed: the stream left over after the chunks continues the last one), at every line
// rate, ended by the client's writes, with noise between them, with broken CRCs to repair, and
// one frame cut at and just past t1.5 and t3.5. Gap values: fuzz_wire_modbus.cpp.
constexpr std::uint8_t kModbusT15 = 64;        // exactly t1.5: the frame goes on
constexpr std::uint8_t kModbusOverT15 = 65;    // just over: the frame is broken
constexpr std::uint8_t kModbusUnderT35 = 127;  // broken, not yet ended
constexpr std::uint8_t kModbusT35 = 128;       // exactly t3.5: the frame ends
constexpr std::uint8_t kModbusOverT35 = 129;
constexpr std::uint8_t kModbusRates = 8;  // fuzz_wire_modbus.cpp's kRates
constexpr std::size_t kMaxChunkBytes = 255;

using Frames = std::vector<std::vector<std::uint8_t>>;

// Writes `frames` as seeds of up to 15 frames each, one chunk per frame with `gap` before every
// frame but the first (frames longer than a chunk take two, the second with no gap).
void write_modbus_streams(const fs::path& dir, const std::string& name, const Frames& frames,
                          std::uint8_t gap, std::uint8_t rate, bool repair) {
  std::size_t part = 0;
  for (std::size_t first = 0; first < frames.size(); ++part) {
    std::vector<Chunk> chunks;
    std::vector<std::uint8_t> stream;
    std::size_t i = first;
    for (; i < frames.size(); ++i) {
      const std::size_t pieces = frames[i].size() > kMaxChunkBytes ? 2 : 1;
      if (chunks.size() + pieces > dxlemu::fuzz::kMaxChunks) {
        break;
      }
      const std::size_t head = std::min(frames[i].size(), kMaxChunkBytes);
      chunks.push_back(Chunk{static_cast<std::uint8_t>(head), i == first ? std::uint8_t{0} : gap});
      if (pieces == 2) {
        chunks.push_back(Chunk{static_cast<std::uint8_t>(frames[i].size() - head), 0});
      }
      append(stream, frames[i]);
    }
    write_seed(dir, name + "." + std::to_string(part), chunks, repair, stream, rate);
    first = i;
  }
}

void make_modbus_corpus(const fs::path& dir) {
  fs::create_directories(dir);
  Frames frames;
  for (const auto& seed : dxlemu::test::modbus_seed_frames()) {
    write_seed(dir, "modbus." + std::string(seed.name), {}, false, seed.bytes);
    frames.push_back(seed.bytes);
  }
  std::vector<std::uint8_t> all;
  for (const auto& f : frames) {
    append(all, f);
  }
  // No silence at all: one overlong frame.
  write_seed(dir, "all_frames", {}, false, all);
  for (std::uint8_t rate = 0; rate < kModbusRates; ++rate) {
    write_modbus_streams(dir, "silences.rate" + std::to_string(rate), frames, kModbusT35, rate,
                         false);
  }
  write_modbus_streams(dir, "end_of_write", frames, dxlemu::fuzz::kGapEndOfWrite, 0, false);
  write_modbus_streams(dir, "to_deadline", frames, dxlemu::fuzz::kGapToDeadline, 0, false);
  write_modbus_streams(dir, "over_t35", frames, kModbusOverT35, 1, false);  // 9600 bit/s

  // Noise between frames: a lone byte and three bytes (too short: Truncated).
  Frames noisy;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    noisy.push_back(i % 2 == 0 ? std::vector<std::uint8_t>{0x00}
                               : std::vector<std::uint8_t>{0x01, 0x03, 0xFF});
    noisy.push_back(frames[i]);
  }
  write_modbus_streams(dir, "noise", noisy, kModbusT35, 0, false);

  // Broken CRCs, for the repair flag to fix.
  Frames broken = frames;
  for (auto& f : broken) {
    f.back() ^= 0xFFU;
  }
  write_modbus_streams(dir, "repaired", broken, kModbusT35, 0, true);

  // One request cut into pieces with each kind of gap between them, at 57600 and at 9600 bit/s
  // (fixed and character-time silences).
  const std::vector<std::uint8_t>& request = frames.at(0);
  for (std::uint8_t rate : {std::uint8_t{0}, std::uint8_t{1}}) {
    std::vector<Chunk> cuts;
    std::vector<std::uint8_t> stream;
    for (const std::uint8_t gap :
         {kModbusT15, kModbusOverT15, kModbusUnderT35, kModbusT35, kModbusOverT35,
          dxlemu::fuzz::kGapToDeadline, dxlemu::fuzz::kGapEndOfWrite}) {
      cuts.push_back(Chunk{3, cuts.empty() ? std::uint8_t{0} : kModbusT35});
      cuts.push_back(Chunk{static_cast<std::uint8_t>(request.size() - 3), gap});
      append(stream, request);
    }
    write_seed(dir, "cut_gaps.rate" + std::to_string(rate), cuts, false, stream, rate);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view protocol = argc == 4 ? argv[1] : "";
  if (protocol != "1" && protocol != "2" && protocol != "feetech" && protocol != "modbus") {
    std::cerr << "usage: make_fuzz_corpus <1|2|feetech|modbus> <golden_packets.txt> <output "
                 "directory>\n";
    return 2;
  }
  try {
    if (protocol == "feetech") {
      make_corpus(feetech_seeds(), argv[3]);
    } else if (protocol == "modbus") {
      make_modbus_corpus(argv[3]);
    } else {
      const auto p = protocol == "1" ? dxlemu::wire::Protocol::V1 : dxlemu::wire::Protocol::V2;
      make_corpus(golden_seeds(p, argv[2]), argv[3]);
    }
  } catch (const std::exception& e) {
    std::cerr << "make_fuzz_corpus: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
