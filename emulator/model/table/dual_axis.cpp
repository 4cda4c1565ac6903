#include "model/table/dual_axis.hpp"

namespace dxlemu::model {

void link_axes(ControlTable& first, ControlTable& second) {
  const auto both_off = [&first, &second] {
    return first.get("torque_enable") == 0 && second.get("torque_enable") == 0;
  };
  first.set_eeprom_lock([both_off] { return !both_off(); });
  second.set_eeprom_lock([both_off] { return !both_off(); });
  for (const std::string& key : first.spec().shared_items) {
    // set() bypasses hooks, so the copy does not echo back.
    first.on_write(key, [&first, &second](std::size_t item, std::int64_t, std::int64_t) {
      second.set(item, first.get(item));
    });
    second.on_write(key, [&first, &second](std::size_t item, std::int64_t, std::int64_t) {
      first.set(item, second.get(item));
    });
  }
}

}  // namespace dxlemu::model
