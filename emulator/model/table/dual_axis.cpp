#include "model/table/dual_axis.hpp"

#include "model/item_hooks.hpp"

namespace dxlemu::model {

void link_axes(ControlTable& first, ControlTable& second) {
  const auto both_off = [&first, &second] {
    return first.get("torque_enable") == 0 && second.get("torque_enable") == 0;
  };
  first.set_eeprom_lock([both_off] { return !both_off(); });
  second.set_eeprom_lock([both_off] { return !both_off(); });
  install_item_hooks(HookScope{first, nullptr, &second}, HookNeeds::OtherAxis);
  install_item_hooks(HookScope{second, nullptr, &first}, HookNeeds::OtherAxis);
}

void copy_to_other_axis(const ControlTable& from, ControlTable& to, std::size_t item) {
  to.set(item, from.get(item));
}

}  // namespace dxlemu::model
