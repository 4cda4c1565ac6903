#include "bus/line_timing.hpp"

namespace dxlemu::bus {
namespace {

constexpr std::int64_t kBitsPerByte = 10;  // start bit, 8 data bits, stop bit
constexpr std::int64_t kNanosPerSecond = 1'000'000'000;
constexpr std::uint64_t kToleranceNumerator = 3;  // 3 %
constexpr std::uint64_t kToleranceDenominator = 100;

}  // namespace

sim::SimDuration wire_time(std::size_t bytes, std::uint32_t bps) {
  if (bps == 0) {
    return sim::SimDuration::zero();
  }
  const std::int64_t bits = static_cast<std::int64_t>(bytes) * kBitsPerByte;
  return sim::SimDuration{(bits * kNanosPerSecond + bps - 1) / bps};
}

bool baud_matches(std::uint32_t client_bps, std::uint32_t servo_bps) {
  if (client_bps == 0 || servo_bps == 0) {
    return false;
  }
  const std::uint64_t diff =
      client_bps > servo_bps ? client_bps - servo_bps : servo_bps - client_bps;
  return diff * kToleranceDenominator <= std::uint64_t{servo_bps} * kToleranceNumerator;
}

}  // namespace dxlemu::bus
