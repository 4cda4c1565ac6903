#include "sim/rng.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace {

using dxlemu::sim::RandomStream;
using dxlemu::sim::Rng;

constexpr std::size_t kSampleCount = 1'000;
constexpr std::uint64_t kMaxU64 = std::numeric_limits<std::uint64_t>::max();
constexpr int kDoubleBits = 53;
constexpr int kDiscardedBits = 64 - kDoubleBits;

std::vector<std::uint64_t> draw(RandomStream& stream, std::size_t count) {
  std::vector<std::uint64_t> values;
  values.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    values.push_back(stream.next_u64());
  }
  return values;
}

}  // namespace

TEST_CASE("xoshiro256** matches its reference output for the state {1, 2, 3, 4}", "[sim]") {
  // From the reference algorithm: result = rotl(s[1] * 5, 7) * 9, so s[1] = 2 gives 11520; after
  // one step s[1] = 0, giving 0.
  auto stream = RandomStream::from_state({1, 2, 3, 4});
  CHECK(stream.next_u64() == 11520);
  CHECK(stream.next_u64() == 0);
}

TEST_CASE("Rng(42) stream \"faults\" produces its pinned golden values", "[sim]") {
  // Pinned once from this implementation (and cross-checked against an independent transcription
  // of splitmix64, FNV-1a and xoshiro256**). A change here means old seeds no longer replay.
  Rng rng(42);
  auto& faults = rng.stream("faults");
  CHECK(faults.next_u64() == 0x3696b3fa4b859636ULL);
  CHECK(faults.next_u64() == 0xd98d7e756ae74d5eULL);
  CHECK(faults.next_u64() == 0x82d873a1bfd01233ULL);
}

TEST_CASE("The same seed and stream name give the same sequence", "[sim]") {
  Rng first(7);
  Rng second(7);
  CHECK(draw(first.stream("noise"), kSampleCount) == draw(second.stream("noise"), kSampleCount));
  CHECK(first.seed() == 7);
}

TEST_CASE("Different stream names or seeds give different sequences", "[sim]") {
  Rng rng(7);
  Rng other_seed(8);
  const auto a = draw(rng.stream("a"), kSampleCount);
  const auto b = draw(rng.stream("b"), kSampleCount);
  const auto a_other_seed = draw(other_seed.stream("a"), kSampleCount);
  CHECK(a != b);
  CHECK(a != a_other_seed);
}

TEST_CASE("stream() returns the same object for the same name", "[sim]") {
  Rng rng(1);
  auto& first = rng.stream("bus");
  first.next_u64();
  rng.stream("other");
  CHECK(&rng.stream("bus") == &first);
  CHECK(&rng.stream(std::string("bus")) == &first);
}

TEST_CASE("Drawing from one stream never shifts another, whatever the creation order", "[sim]") {
  Rng untouched(99);
  const auto b_alone = draw(untouched.stream("b"), kSampleCount);

  SECTION("a created and drawn from first") {
    Rng rng(99);
    draw(rng.stream("a"), kSampleCount);
    CHECK(draw(rng.stream("b"), kSampleCount) == b_alone);
  }
  SECTION("b created first, a drawn from in between") {
    Rng rng(99);
    auto& b = rng.stream("b");
    const auto first_half = draw(b, kSampleCount / 2);
    draw(rng.stream("a"), kSampleCount);
    auto values = first_half;
    const auto second_half = draw(b, kSampleCount / 2);
    values.insert(values.end(), second_half.begin(), second_half.end());
    CHECK(values == b_alone);
  }
}

TEST_CASE("uniform stays within its inclusive bounds", "[sim]") {
  Rng rng(3);
  auto& stream = rng.stream("uniform");

  SECTION("a small range hits every value and nothing outside") {
    std::set<std::uint64_t> seen;
    for (std::size_t i = 0; i < kSampleCount; ++i) {
      const auto value = stream.uniform(10, 15);
      REQUIRE(value >= 10);
      REQUIRE(value <= 15);
      seen.insert(value);
    }
    CHECK(seen == std::set<std::uint64_t>{10, 11, 12, 13, 14, 15});
  }
  SECTION("lo == hi returns that value") {
    CHECK(stream.uniform(0, 0) == 0);
    CHECK(stream.uniform(42, 42) == 42);
    CHECK(stream.uniform(kMaxU64, kMaxU64) == kMaxU64);
  }
  SECTION("the full 64-bit range is allowed") {
    std::set<std::uint64_t> seen;
    for (std::size_t i = 0; i < kSampleCount; ++i) {
      seen.insert(stream.uniform(0, kMaxU64));
    }
    CHECK(seen.size() > kSampleCount - 2);
  }
  SECTION("ranges at the top of the 64-bit range") {
    for (std::size_t i = 0; i < kSampleCount; ++i) {
      const auto value = stream.uniform(kMaxU64 - 2, kMaxU64);
      REQUIRE(value >= kMaxU64 - 2);
    }
    for (std::size_t i = 0; i < kSampleCount; ++i) {
      const auto value = stream.uniform(1, kMaxU64);
      REQUIRE(value >= 1);
    }
  }
}

TEST_CASE("bernoulli(0) is never true and bernoulli(1) is always true", "[sim]") {
  Rng rng(5);
  auto& stream = rng.stream("coin");
  for (std::size_t i = 0; i < kSampleCount; ++i) {
    REQUIRE_FALSE(stream.bernoulli(0.0));
    REQUIRE_FALSE(stream.bernoulli(-1.0));
    REQUIRE(stream.bernoulli(1.0));
    REQUIRE(stream.bernoulli(2.0));
  }
}

TEST_CASE("bernoulli(0.5) comes up true roughly half the time", "[sim]") {
  Rng rng(5);
  auto& stream = rng.stream("coin");
  std::size_t trues = 0;
  for (std::size_t i = 0; i < kSampleCount; ++i) {
    trues += stream.bernoulli(0.5) ? 1 : 0;
  }
  // Deterministic for this seed; the margin only guards against a gross error.
  CHECK(trues > kSampleCount * 4 / 10);
  CHECK(trues < kSampleCount * 6 / 10);
}

TEST_CASE("uniform01 is at least 0 and below 1", "[sim]") {
  Rng rng(11);
  auto& stream = rng.stream("unit");
  double lowest = 1.0;
  double highest = 0.0;
  for (std::size_t i = 0; i < kSampleCount; ++i) {
    const double value = stream.uniform01();
    REQUIRE(value >= 0.0);
    REQUIRE(value < 1.0);
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
  }
  CHECK(lowest < 0.01);
  CHECK(highest > 0.99);
}

TEST_CASE("uniform01 uses the top 53 bits of one draw", "[sim]") {
  auto bits = RandomStream::from_state({1, 2, 3, 4});
  auto unit = RandomStream::from_state({1, 2, 3, 4});
  const std::uint64_t raw = bits.next_u64();
  CHECK(unit.uniform01() ==
        static_cast<double>(raw >> kDiscardedBits) / static_cast<double>(1ULL << kDoubleBits));
  CHECK(unit.state() == bits.state());
}
