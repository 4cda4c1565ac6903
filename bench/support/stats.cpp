#include "support/stats.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace dxlemu::bench {

std::chrono::nanoseconds percentile(const std::vector<std::chrono::nanoseconds>& sorted, double p) {
  const auto n = static_cast<double>(sorted.size());
  return sorted[std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p * n))) - 1];
}

std::string us(std::chrono::nanoseconds d) {
  constexpr double kNanosPerMicro = 1000.0;
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%.1f", static_cast<double>(d.count()) / kNanosPerMicro);
  return text.data();
}

std::string fixed(double value, int decimals) {
  std::array<char, 64> text{};
  std::snprintf(text.data(), text.size(), "%.*f", decimals, value);
  return text.data();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 != 0 ? values[mid] : (values[mid - 1] + values[mid]) / 2;
}

}  // namespace dxlemu::bench
