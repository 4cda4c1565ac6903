// Servo's device side as the control API drives it: writes that no instruction carried. Kept
// apart from servo.cpp, which executes instructions.
#include <algorithm>

#include "model/item_hooks.hpp"
#include "model/servo.hpp"

namespace dxlemu::model {

bool Servo::defers(std::size_t item_index) const {
  // The item hook table names the items commit_deferred() reads.
  return applies_after_status(spec(), item_index);
}

void Servo::device_write(std::size_t item_index, std::int64_t value) {
  const ItemSpec& item = spec().items.at(item_index);
  const std::vector<std::uint8_t> bytes = table_.encoded(item_index, value);
  // A Write at an Indirect Data address lands at the address it maps, not in the item itself.
  const bool indirect_data =
      std::any_of(spec().indirect.begin(), spec().indirect.end(), [&](const IndirectBlock& block) {
        return item.address >= block.data && item.address < block.data + block.count;
      });
  // The rules of the protocol the servo speaks decide only whether its hooks hear of the change.
  const wire::Protocol protocol = protocol_.value_or(
      spec().protocols.empty() ? wire::kDefaultProtocol : spec().protocols.front());
  if (!indirect_data && table_.check_write(item.address, bytes, protocol).ok()) {
    table_.bus_write(item.address, bytes, protocol);
  } else {
    table_.set(item_index, value);
    // No hook heard it: a Homing Offset or Drive Mode forced in shows in the Present values now.
    motion_.setting_forced(item_index);
  }
  // Present values set device-side move the shaft, the winding or the supply there.
  motion_.wake();
  if (defers(item_index)) {
    commit_deferred();
  }
}

}  // namespace dxlemu::model
