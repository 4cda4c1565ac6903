#include "wire/listed_ids.hpp"

#include <algorithm>
#include <type_traits>

namespace dxlemu::wire {

std::vector<std::uint8_t> listed_ids(const InstructionPacket& packet) {
  std::vector<std::uint8_t> ids;
  const auto add = [&](std::uint8_t id) {
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) {
      ids.push_back(id);
    }
  };
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_base_of_v<SyncRead, T>) {
          std::for_each(ins.ids.begin(), ins.ids.end(), add);
        } else if constexpr (requires { ins.targets; }) {
          for (const auto& t : ins.targets) {
            add(t.id);
          }
        }
      },
      packet.instruction);
  return ids;
}

}  // namespace dxlemu::wire
