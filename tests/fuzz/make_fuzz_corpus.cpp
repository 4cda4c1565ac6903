// Writes the seed corpus of one fuzz target: every golden packet of the protocol as its own input,
// plus a few combined inputs that start the fuzzer off with several packets per stream, garbage
// between them, split chunks and inter-byte timeouts. The corpus is derived at build time from
// tests/data/golden_packets.txt (DYNAMIXEL) or FEETECH's example frames (feetech_examples.cpp) and
// never committed.
//
// Usage: make_fuzz_corpus <1|2|feetech> <golden_packets.txt> <output directory>

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
                bool repair_checks, std::span<const std::uint8_t> stream) {
  const std::vector<std::uint8_t> input =
      dxlemu::fuzz::build_fuzz_input(chunks, repair_checks, stream);
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

}  // namespace

int main(int argc, char** argv) {
  const std::string_view protocol = argc == 4 ? argv[1] : "";
  if (protocol != "1" && protocol != "2" && protocol != "feetech") {
    std::cerr << "usage: make_fuzz_corpus <1|2|feetech> <golden_packets.txt> <output directory>\n";
    return 2;
  }
  try {
    if (protocol == "feetech") {
      make_corpus(feetech_seeds(), argv[3]);
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
