#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace dxlemu::sim {

/// One deterministic stream of pseudo-random numbers: xoshiro256** (Blackman and Vigna) seeded
/// through splitmix64. Every output is fully specified here, never by the standard library, so a
/// given seed replays the same values on every platform and compiler. Copying a stream forks it:
/// the copy continues with the same values as the original.
class RandomStream {
 public:
  /// The generator's 256-bit state, four 64-bit words s[0..3] as in the reference implementation.
  using State = std::array<std::uint64_t, 4>;

  /// Creates a stream whose state is the first four outputs of splitmix64 started at `seed`
  /// (the seeding recommended by xoshiro's authors; it never yields the invalid all-zero state).
  explicit RandomStream(std::uint64_t seed);

  /// Creates a stream from an explicit state (must not be all zeros), e.g. to check the generator
  /// against its published reference outputs.
  static RandomStream from_state(const State& state);

  /// The current state; feeding it to from_state() continues this stream's sequence.
  [[nodiscard]] const State& state() const { return s_; }

  /// The next 64 raw bits (xoshiro256** output).
  std::uint64_t next_u64();

  /// A uniformly distributed integer in [lo, hi], both inclusive; lo must not exceed hi. Unbiased
  /// (rejection sampling); lo == hi draws nothing and returns lo; the full 64-bit range is allowed.
  std::uint64_t uniform(std::uint64_t lo, std::uint64_t hi);

  /// A uniformly distributed double in [0, 1), built from the top 53 bits of one next_u64().
  double uniform01();

  /// True with probability `p`. p <= 0 is never true and p >= 1 always true; in those two cases
  /// nothing is drawn. Otherwise exactly one next_u64() is drawn (uniform01() < p).
  bool bernoulli(double p);

 private:
  explicit RandomStream(const State& state);

  State s_;
};

/// The emulator's source of randomness: one seed (from `--seed N`) and named, independent streams.
/// Each stream's seed depends only on (seed, name), so drawing from one stream, or creating streams
/// in a different order, never changes another stream's values: fault injection replays exactly.
/// Not copyable (a copy would replay the same "random" faults twice); movable.
class Rng {
 public:
  /// Creates a generator with the given seed and no streams yet.
  explicit Rng(std::uint64_t seed) : seed_(seed) {}

  Rng(const Rng&) = delete;
  Rng& operator=(const Rng&) = delete;
  Rng(Rng&&) = default;
  Rng& operator=(Rng&&) = default;
  ~Rng() = default;

  /// The stream called `name`, created on first use. The same name always yields the same object;
  /// the reference stays valid for the lifetime of this Rng (also across moves). Owned by the Rng.
  RandomStream& stream(std::string_view name);

  /// The seed this generator was created with.
  [[nodiscard]] std::uint64_t seed() const { return seed_; }

 private:
  std::uint64_t seed_;
  // std::less<> allows lookup by string_view; map nodes keep references stable.
  std::map<std::string, RandomStream, std::less<>> streams_;
};

}  // namespace dxlemu::sim
