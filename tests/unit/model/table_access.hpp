#pragma once

#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "model/table/control_table.hpp"

namespace dxlemu::test {

/// A bus write's outcome: only the error, which is what the access-rule tests compare.
inline model::TableError write(model::ControlTable& t, std::uint16_t address,
                               std::vector<std::uint8_t> data,
                               wire::Protocol protocol = wire::Protocol::V2) {
  return t.bus_write(address, data, protocol).error;
}

/// A bus read that must succeed.
inline std::vector<std::uint8_t> read(model::ControlTable& t, std::uint16_t address,
                                      std::uint16_t length) {
  std::vector<std::uint8_t> out;
  REQUIRE(t.bus_read(address, length, out).ok());
  return out;
}

/// `value` as `n` little-endian bytes (two's complement for negative values).
inline std::vector<std::uint8_t> le(std::int64_t value, std::size_t n) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i)));
  }
  return out;
}

/// The value of the little-endian `bytes` of an item, two's complement when `is_signed`.
inline std::int64_t from_le(const std::vector<std::uint8_t>& bytes, bool is_signed) {
  std::uint64_t raw = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    raw |= std::uint64_t{bytes[i]} << (8 * i);
  }
  const std::size_t bits = 8 * bytes.size();
  auto value = static_cast<std::int64_t>(raw);
  if (is_signed && bits > 0 && bits < 64 && (raw >> (bits - 1)) != 0) {
    value -= std::int64_t{1} << bits;
  }
  return value;
}

}  // namespace dxlemu::test
