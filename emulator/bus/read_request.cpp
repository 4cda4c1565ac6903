#include "bus/read_request.hpp"

#include <algorithm>
#include <type_traits>

namespace dxlemu::bus {

ReadRequest read_request(const wire::InstructionPacket& packet) {
  ReadRequest out;
  auto add = [&](const ReadPart& part) {
    if (std::none_of(out.parts.begin(), out.parts.end(),
                     [&](const ReadPart& s) { return s.id == part.id; })) {
      out.parts.push_back(part);
    }
  };
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_base_of_v<wire::SyncRead, T>) {
          out.fast = std::is_same_v<T, wire::FastSyncRead>;
          for (const std::uint8_t id : ins.ids) {
            add({id, ins.address, ins.length});
          }
        } else if constexpr (std::is_base_of_v<wire::BulkRead, T>) {
          out.fast = std::is_same_v<T, wire::FastBulkRead>;
          out.v1_bulk = wire::traits(packet.protocol).bulk_read_needs_support;
          for (const wire::BulkReadTarget& t : ins.targets) {
            add({t.id, t.address, t.length});
          }
        }
      },
      packet.instruction);
  return out;
}

bool is_group_instruction(wire::Protocol protocol, std::uint8_t code) {
  const wire::InstructionInfo* info = wire::instruction_info(protocol, code);
  return info != nullptr && (info->role == wire::InstructionRole::GroupRead ||
                             info->role == wire::InstructionRole::GroupWrite);
}

}  // namespace dxlemu::bus
