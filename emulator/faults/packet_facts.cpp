#include "faults/packet_facts.hpp"

#include <algorithm>
#include <type_traits>

namespace dxlemu::faults {

namespace {

using Span = std::pair<std::uint16_t, std::uint16_t>;

std::optional<Span> span(std::uint16_t address, std::size_t length) {
  if (length == 0) {
    return std::nullopt;
  }
  const std::size_t last = std::min<std::size_t>(address + length - 1, 0xFFFF);
  return Span{address, static_cast<std::uint16_t>(last)};
}

// The smallest span covering both.
std::optional<Span> cover(std::optional<Span> a, std::optional<Span> b) {
  if (!a || !b) {
    return a ? a : b;
  }
  return Span{std::min(a->first, b->first), std::max(a->second, b->second)};
}

template <class Target>
std::optional<Span> bulk_span(const std::vector<Target>& targets, std::optional<std::uint8_t> id) {
  std::optional<Span> out;
  for (const Target& t : targets) {
    std::optional<Span> part;
    if constexpr (requires { t.length; }) {
      part = span(t.address, t.length);
    } else {
      part = span(t.address, t.data.size());
    }
    if (id && t.id == *id) {
      return part;  // a servo executes only the first part listed for it
    }
    if (!id) {
      out = cover(out, part);
    }
  }
  return out;
}

}  // namespace

std::optional<Span> span_of(const wire::InstructionPacket& packet, std::optional<std::uint8_t> id) {
  return std::visit(
      [&](const auto& ins) -> std::optional<Span> {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, wire::Read> || std::is_base_of_v<wire::SyncRead, T> ||
                      std::is_same_v<T, wire::SyncWrite>) {
          return span(ins.address, ins.length);
        } else if constexpr (std::is_same_v<T, wire::Write> || std::is_same_v<T, wire::RegWrite>) {
          return span(ins.address, ins.data.size());
        } else if constexpr (std::is_base_of_v<wire::BulkRead, T> ||
                             std::is_same_v<T, wire::BulkWrite>) {
          return bulk_span(ins.targets, id);
        } else {
          return std::nullopt;
        }
      },
      packet.instruction);
}

}  // namespace dxlemu::faults
