#include "wire/stuffing.hpp"

#include <cstddef>

namespace dxlemu::wire {
namespace {

constexpr std::uint8_t kFf = 0xFF;
constexpr std::uint8_t kFd = 0xFD;

// True when bytes[i-2..i] are FF FF FD. FF FF FD cannot overlap itself, so every occurrence in
// the original region maps to exactly one FF FF FD FD in the stuffed region and vice versa.
bool ends_header_pattern(std::span<const std::uint8_t> bytes, std::size_t i) {
  return i >= 2 && bytes[i] == kFd && bytes[i - 1] == kFf && bytes[i - 2] == kFf;
}

}  // namespace

std::vector<std::uint8_t> stuff(std::span<const std::uint8_t> region) {
  std::vector<std::uint8_t> out;
  out.reserve(region.size() + region.size() / 3 + 1);
  for (std::size_t i = 0; i < region.size(); ++i) {
    out.push_back(region[i]);
    if (ends_header_pattern(region, i)) {
      out.push_back(kFd);
    }
  }
  return out;
}

std::vector<std::uint8_t> unstuff(std::span<const std::uint8_t> region) {
  std::vector<std::uint8_t> out;
  out.reserve(region.size());
  for (std::size_t i = 0; i < region.size(); ++i) {
    out.push_back(region[i]);
    if (ends_header_pattern(region, i) && i + 1 < region.size() && region[i + 1] == kFd) {
      ++i;  // the stuffed 0xFD
    }
  }
  return out;
}

}  // namespace dxlemu::wire
