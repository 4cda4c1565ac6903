#include "sim/rng.hpp"

#include <bit>
#include <cassert>
#include <limits>

namespace dxlemu::sim {

namespace {

// splitmix64 constants, from Vigna's reference splitmix64.c (https://prng.di.unimi.it/).
constexpr std::uint64_t kSplitMixIncrement = 0x9e3779b97f4a7c15ULL;
constexpr std::uint64_t kSplitMixMul1 = 0xbf58476d1ce4e5b9ULL;
constexpr std::uint64_t kSplitMixMul2 = 0x94d049bb133111ebULL;

// FNV-1a 64-bit parameters (http://www.isthe.com/chongo/tech/comp/fnv/).
constexpr std::uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

// uniform01(): a double has a 53-bit significand, so the top 53 bits scaled by 2^-53 give every
// representable multiple of 2^-53 in [0, 1) with equal probability, and never 1.0.
constexpr int kDoubleBits = 53;
constexpr int kDiscardedBits = 64 - kDoubleBits;
constexpr double kTwoPowMinus53 = 0x1.0p-53;

// Advances the splitmix64 state and returns its next output.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += kSplitMixIncrement);
  z = (z ^ (z >> 30)) * kSplitMixMul1;
  z = (z ^ (z >> 27)) * kSplitMixMul2;
  return z ^ (z >> 31);
}

std::uint64_t fnv1a64(std::string_view text) {
  std::uint64_t hash = kFnvOffsetBasis;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= kFnvPrime;
  }
  return hash;
}

// A stream's seed from (seed, name). Mixing the seed before combining it with the name hash keeps
// nearby seeds (1, 2, 3...) from producing related stream seeds; the final splitmix64 spreads the
// combination over all 64 bits. Depends on nothing else, in particular not on creation order.
std::uint64_t derive_stream_seed(std::uint64_t seed, std::string_view name) {
  std::uint64_t mixed_seed = seed;
  std::uint64_t combined = splitmix64(mixed_seed) ^ fnv1a64(name);
  return splitmix64(combined);
}

RandomStream::State state_from_seed(std::uint64_t seed) {
  RandomStream::State state{};
  for (auto& word : state) {
    word = splitmix64(seed);
  }
  return state;
}

}  // namespace

RandomStream::RandomStream(std::uint64_t seed) : s_(state_from_seed(seed)) {}

RandomStream::RandomStream(const State& state) : s_(state) {
  // All zeros is xoshiro's single fixed point: it would output 0 forever.
  assert((s_[0] | s_[1] | s_[2] | s_[3]) != 0 && "RandomStream: all-zero state");
}

RandomStream RandomStream::from_state(const State& state) {
  return RandomStream(state);
}

std::uint64_t RandomStream::next_u64() {
  // xoshiro256** 1.0, transcribed from Blackman and Vigna's xoshiro256starstar.c.
  const std::uint64_t result = std::rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = std::rotl(s_[3], 45);
  return result;
}

std::uint64_t RandomStream::uniform(std::uint64_t lo, std::uint64_t hi) {
  assert(lo <= hi && "RandomStream::uniform: lo > hi");
  const std::uint64_t span = hi - lo;
  if (span == 0) {
    return lo;
  }
  if (span == std::numeric_limits<std::uint64_t>::max()) {
    return next_u64();
  }
  const std::uint64_t count = span + 1;
  // Rejection on the low end: 2^64 mod count values would make x % count favour small results, so
  // draws below threshold = (2^64 - count) mod count = (-count) % count are thrown away. What is
  // left is a whole number of copies of [0, count). Chosen over Lemire's multiply-shift because it
  // needs no 128-bit arithmetic, which ISO C++ lacks; speed does not matter here.
  const std::uint64_t threshold = (0 - count) % count;
  std::uint64_t x = next_u64();
  while (x < threshold) {
    x = next_u64();
  }
  return lo + x % count;
}

double RandomStream::uniform01() {
  return static_cast<double>(next_u64() >> kDiscardedBits) * kTwoPowMinus53;
}

bool RandomStream::bernoulli(double p) {
  if (p <= 0.0) {
    return false;
  }
  if (p >= 1.0) {
    return true;
  }
  return uniform01() < p;
}

RandomStream& Rng::stream(std::string_view name) {
  const auto found = streams_.find(name);
  if (found != streams_.end()) {
    return found->second;
  }
  return streams_.emplace(std::string(name), RandomStream(derive_stream_seed(seed_, name)))
      .first->second;
}

}  // namespace dxlemu::sim
