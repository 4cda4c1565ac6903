#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace dxlemu::bench {

/// Nearest-rank percentile `p` (0 < p <= 1) of `sorted` (ascending, not empty): the smallest
/// sample with at least p of the samples at or below it.
std::chrono::nanoseconds percentile(const std::vector<std::chrono::nanoseconds>& sorted, double p);

/// `d` in microseconds with one decimal ("12.3").
std::string us(std::chrono::nanoseconds d);

/// `value` with `decimals` digits after the point ("3.14").
std::string fixed(double value, int decimals);

/// The median of `values` (not empty): the middle value, or the mean of the two middle ones.
double median(std::vector<double> values);

}  // namespace dxlemu::bench
