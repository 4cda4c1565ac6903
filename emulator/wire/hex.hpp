#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dxlemu::wire {

/// Bytes as uppercase two-digit hex separated by single spaces ("FF FF FD 00"); "" when empty.
std::string to_hex(std::span<const std::uint8_t> bytes);

/// Parses whitespace-separated two-digit hex bytes ("ff FF 0x01" is not accepted: no prefixes).
/// Returns nullopt on anything else.
std::optional<std::vector<std::uint8_t>> parse_hex(std::string_view text);

}  // namespace dxlemu::wire
