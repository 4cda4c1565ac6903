#include "model/table/control_table.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "model/item_hooks.hpp"
#include "model/table/item_encoding.hpp"

namespace dxlemu::model {
namespace {

constexpr int kNoItem = -1;

std::string describe_item(const ItemSpec& item) {
  return item.key + " (" + std::to_string(item.address) + ")";
}

// Device-side writes may bypass every rule but the item's size.
void require_fits(const ItemSpec& item, std::int64_t value) {
  if (!ControlTable::fits(item, value)) {
    throw std::invalid_argument(std::to_string(value) + " does not fit " + describe_item(item) +
                                " (" + std::to_string(item.size) + " bytes)");
  }
}

}  // namespace

ControlTable::ControlTable(std::shared_ptr<const ModelSpec> spec)
    : spec_(std::move(spec)),
      image_(spec_->table_size(), 0),
      hybrid_saved_(spec_->items.size(), 0),
      item_at_(spec_->table_size(), kNoItem),
      indirect_address_(spec_->table_size(), kNoItem),
      write_hooks_(spec_->items.size()),
      validators_(spec_->items.size()),
      range_rules_(spec_->items.size()),
      torque_enable_(spec_->index_of("torque_enable")),
      lock_(spec_->index_of("lock")),
      id_(spec_->index_of("id")) {
  for (std::size_t i = 0; i < spec_->items.size(); ++i) {
    const ItemSpec& item = spec_->items[i];
    if (item.size > kMaxItemBytes) {
      throw std::invalid_argument(describe_item(item) + " is wider than " +
                                  std::to_string(kMaxItemBytes) + " bytes");
    }
    std::fill_n(item_at_.begin() + item.address, item.size, static_cast<int>(i));
  }
  for (const IndirectBlock& block : spec_->indirect) {
    for (std::uint16_t i = 0; i < block.count; ++i) {
      indirect_address_[block.data + i] = item_at_[block.address + 2 * i];
    }
  }
  load_initial(true);
  install_item_hooks(HookScope{*this}, HookNeeds::Table);
}

void ControlTable::load_initial(bool eeprom) {
  if (!eeprom && eeprom_keep_) {
    // FEETECH: EEPROM writes made while the Lock flag was 1 are lost at power-off (first: RAM
    // items may start from EEPROM ones).
    for (std::size_t i = 0; i < spec_->items.size(); ++i) {
      if (spec_->items[i].area == Area::Eeprom && get(i) != eeprom_kept_[i]) {
        ++eeprom_changes_;
        encode(spec_->items[i], eeprom_kept_[i],
               std::span(image_).subspan(spec_->items[i].address, spec_->items[i].size));
      }
    }
  }
  // Items that copy another item's value at power-on (AX Torque Limit = Max Torque) read the
  // value that item has now, so they go second.
  for (const bool copies : {false, true}) {
    for (std::size_t i = 0; i < spec_->items.size(); ++i) {
      const ItemSpec& item = spec_->items[i];
      if ((item.area == Area::Eeprom && !eeprom) || item.initial_from.has_value() != copies) {
        continue;
      }
      const std::int64_t initial = item.initial_from ? get(*item.initial_from) : item.initial;
      if (item.area == Area::Eeprom && eeprom_keep_) {
        eeprom_kept_[i] = initial;  // a factory reset: the initial values are what is kept
      }
      if (item.area == Area::Hybrid) {
        // _includes/en/dxl/y/control_table_170_hybrid_save.md (ROBOTIS-GIT/emanual): unsaved
        // Hybrid values are lost at reboot or power-off; a factory reset restores the initial.
        if (eeprom) {
          hybrid_saved_[i] = initial;
        }
        set(i, hybrid_saved_[i]);
        continue;
      }
      set(i, initial);
    }
  }
}

void ControlTable::set_eeprom_keep(EepromKeep keep) {
  eeprom_keep_ = std::move(keep);
  eeprom_kept_.assign(spec_->items.size(), 0);
  for (std::size_t i = 0; i < spec_->items.size(); ++i) {
    eeprom_kept_[i] = get(i);
  }
}

std::int64_t ControlTable::kept_value(std::size_t item) const {
  const ItemSpec& spec = spec_->items.at(item);
  if (spec.area == Area::Hybrid) {
    return hybrid_saved_[item];
  }
  return spec.area == Area::Eeprom && eeprom_keep_ ? eeprom_kept_[item] : get(item);
}

void ControlTable::restore_kept(std::size_t item, std::int64_t value) {
  if (spec_->items.at(item).area == Area::Hybrid) {
    restore_hybrid(item, value);
    return;
  }
  set(item, value);
  if (eeprom_keep_ && spec_->items[item].area == Area::Eeprom) {
    eeprom_kept_[item] = value;
  }
}

void ControlTable::keep_if_allowed(std::size_t item, bool keep) {
  if (eeprom_keep_ && keep && spec_->items[item].area == Area::Eeprom) {
    eeprom_kept_[item] = get(item);
  }
}

void ControlTable::save_hybrid() {
  for (std::size_t i = 0; i < spec_->items.size(); ++i) {
    if (spec_->items[i].area == Area::Hybrid && hybrid_saved_[i] != get(i)) {
      hybrid_saved_[i] = get(i);
      ++eeprom_changes_;  // saved values are non-volatile: a state file keeps them
    }
  }
}

void ControlTable::restore_hybrid(std::size_t item, std::int64_t value) {
  if (spec_->items.at(item).area != Area::Hybrid) {
    throw std::invalid_argument(describe_item(spec_->items[item]) + " is not a Hybrid item");
  }
  set(item, value);
  if (hybrid_saved_[item] != value) {
    hybrid_saved_[item] = value;
    ++eeprom_changes_;
  }
}

bool ControlTable::hybrid_changed() const {
  for (std::size_t i = 0; i < spec_->items.size(); ++i) {
    if (spec_->items[i].area == Area::Hybrid && get(i) != hybrid_saved_[i]) {
      return true;
    }
  }
  return false;
}

std::optional<std::uint16_t> ControlTable::resolve(std::uint16_t address) const {
  if (address >= image_.size()) {
    return std::nullopt;
  }
  // includes/control_table_indirect_data.md: Indirect Data n behaves as the address held in
  // Indirect Address n. The mapping is read once, not followed again from the target.
  const int via = indirect_address_[address];
  if (via == kNoItem) {
    return address;
  }
  const auto target = static_cast<std::uint64_t>(get(static_cast<std::size_t>(via)));
  if (target >= image_.size()) {
    return std::nullopt;
  }
  return static_cast<std::uint16_t>(target);
}

TableResult ControlTable::bus_read(std::uint16_t address, std::uint16_t length,
                                   std::vector<std::uint8_t>& out) const {
  out.clear();
  if (std::size_t{address} + length > image_.size()) {
    return TableResult::fail(TableError::Access, "read of " + std::to_string(length) +
                                                     " bytes from " + std::to_string(address) +
                                                     " goes past the end of the table (" +
                                                     std::to_string(image_.size()) + " bytes)");
  }
  out.reserve(length);
  for (std::uint16_t a = address; a < address + length; ++a) {
    const auto target = resolve(a);
    if (!target) {
      out.clear();  // a refused read yields no data
      return TableResult::fail(TableError::Access, "indirect address of " + std::to_string(a) +
                                                       " points outside the table");
    }
    out.push_back(image_[*target]);
  }
  return {};
}

TableResult ControlTable::plan_write(std::uint16_t address, std::span<const std::uint8_t> data,
                                     wire::Protocol protocol) const {
  touched_.clear();
  const bool registers = wire::traits(protocol).register_bytes > 1;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::size_t a = address + i;
    if (registers) {
      if (auto skip = skip_in_register(a, address, data.size(), protocol)) {
        if (!skip->ok()) {
          return *skip;
        }
        continue;
      }
    }
    const auto target = a < image_.size() ? resolve(static_cast<std::uint16_t>(a)) : std::nullopt;
    if (!target || item_at_[*target] == kNoItem) {
      return TableResult::fail(
          TableError::Access, "address " + std::to_string(a) + " is not an item of " + spec_->name);
    }
    const auto item = static_cast<std::size_t>(item_at_[*target]);
    const ItemSpec& spec = spec_->items[item];
    // Consecutive bytes mostly belong to the same item: look at the last one first.
    auto it = !touched_.empty() && touched_.back().item == item
                  ? std::prev(touched_.end())
                  : std::find_if(touched_.begin(), touched_.end(),
                                 [&](const Touched& t) { return t.item == item; });
    if (it == touched_.end()) {
      Touched& t = touched_.emplace_back();
      t.item = item;
      std::copy_n(image_.begin() + spec.address, spec.size, t.bytes.begin());
      it = std::prev(touched_.end());
    }
    it->bytes[*target - spec.address] = data[i];
    ++it->covered;
  }
  std::sort(touched_.begin(), touched_.end(),
            [](const Touched& a, const Touched& b) { return a.item < b.item; });
  return {};
}

std::int64_t ControlTable::value_after(std::size_t item,
                                       const std::vector<Touched>& touched) const {
  for (const Touched& t : touched) {
    if (t.item == item) {
      return decode(spec_->items[item], std::span(t.bytes).first(spec_->items[item].size));
    }
  }
  return get(item);
}

TableResult ControlTable::validate(const std::vector<Touched>& touched,
                                   wire::Protocol protocol) const {
  const bool eeprom_is_locked = eeprom_locked();
  // Access first: a write that touches anything it may not touch fails as a whole with an Access
  // error, whatever the values (protocol2.md "Error": Access Error).
  for (const Touched& t : touched) {
    const ItemSpec& item = spec_->items[t.item];
    if (item.access == Access::ReadOnly) {
      return TableResult::fail(TableError::Access, describe_item(item) + " is read-only");
    }
    if (item.area == Area::Eeprom && eeprom_is_locked) {
      return TableResult::fail(TableError::Locked,
                               describe_item(item) + " is in EEPROM, which is locked " +
                                   (lock_ && get(*lock_) != 0 ? "by Lock" : "while torque is on"));
    }
    // 1.0 Lock: once set, it stays set until power is cycled (includes/control_table_lock.md).
    if (lock_ && t.item == *lock_ && get(*lock_) != 0 &&
        decode(item, std::span(t.bytes).first(item.size)) == 0) {
      return TableResult::fail(TableError::Locked, "Lock stays 1 until the power is cycled");
    }
  }
  // protocol2.md "Data Length Error": a 2.0 write must cover the whole item. Protocol 1.0 has no
  // such error; a partial write there changes the bytes it covers (docs/control-table.md).
  for (const Touched& t : touched) {
    const ItemSpec& item = spec_->items[t.item];
    if (wire::traits(protocol).whole_item_writes && t.covered != item.size) {
      return TableResult::fail(TableError::DataLength, "write covers " + std::to_string(t.covered) +
                                                           " of the " + std::to_string(item.size) +
                                                           " bytes of " + describe_item(item));
    }
  }
  for (const Touched& t : touched) {
    const ItemSpec& item = spec_->items[t.item];
    const std::int64_t value = decode(item, std::span(t.bytes).first(item.size));
    if (const auto range = range_rules_[t.item] ? range_rules_[t.item](t.item) : std::nullopt) {
      if (value < range->min || value > range->max) {
        return TableResult::fail(TableError::DataRange, std::to_string(value) + " is outside " +
                                                            std::to_string(range->min) + " ~ " +
                                                            std::to_string(range->max) + " for " +
                                                            describe_item(item) +
                                                            " in the present mode");
      }
    } else if (TableResult r = check_static_range(item, value, touched); !r.ok()) {
      return r;
    }
    if (TableResult r = check_id(t.item, value, protocol); !r.ok()) {
      return r;
    }
    for (const Validator& v : validators_[t.item]) {
      TableResult r = v(t.item, value);
      if (!r.ok()) {
        return r;
      }
    }
  }
  return {};
}

TableResult ControlTable::check_static_range(const ItemSpec& item, std::int64_t value,
                                             const std::vector<Touched>& touched) const {
  if (!item.in_range(value)) {
    return TableResult::fail(
        TableError::DataRange,
        std::to_string(value) + " is outside the range of " + describe_item(item));
  }
  // A limit item written in the same packet bounds with its new value.
  if (item.limit_min) {
    const std::int64_t bound = value_after(item.limit_min->item, touched);
    const std::int64_t lo = item.limit_min->negate ? -bound : bound;
    if (value < lo) {
      return TableResult::fail(TableError::DataLimit, std::to_string(value) + " is below " +
                                                          (item.limit_min->negate ? "-" : "") +
                                                          spec_->items[item.limit_min->item].key +
                                                          " (" + std::to_string(lo) + ") for " +
                                                          describe_item(item));
    }
  }
  if (item.limit_max) {
    const std::int64_t bound = value_after(item.limit_max->item, touched);
    const std::int64_t hi = item.limit_max->negate ? -bound : bound;
    if (value > hi) {
      return TableResult::fail(TableError::DataLimit, std::to_string(value) + " is above " +
                                                          spec_->items[item.limit_max->item].key +
                                                          " (" + std::to_string(hi) + ") for " +
                                                          describe_item(item));
    }
  }
  return {};
}

TableResult ControlTable::check_write(std::uint16_t address, std::span<const std::uint8_t> data,
                                      wire::Protocol protocol) const {
  if (running_hooks_) {
    throw std::logic_error("a write hook of " + spec_->name + " checked a write to its own table");
  }
  const TableResult planned = plan_write(address, data, protocol);
  return planned.ok() ? validate(touched_, protocol) : planned;
}

TableResult ControlTable::bus_write(std::uint16_t address, std::span<const std::uint8_t> data,
                                    wire::Protocol protocol) {
  TableResult result = check_write(address, data, protocol);
  if (!result.ok()) {
    return result;
  }
  // Whether this write is kept over power-off is decided by the lock as the write arrives.
  const bool keep = !eeprom_keep_ || eeprom_keep_();
  for (Touched& t : touched_) {
    const ItemSpec& item = spec_->items[t.item];
    t.old_value = get(t.item);
    std::copy_n(t.bytes.begin(), item.size, image_.begin() + item.address);
    if (item.area == Area::Eeprom && get(t.item) != t.old_value) {
      ++eeprom_changes_;
    }
    keep_if_allowed(t.item, keep);
  }
  running_hooks_ = true;
  struct Done {
    bool& running;
    ~Done() { running = false; }
  } done{running_hooks_};
  for (const Touched& t : touched_) {
    for (const WriteHook& hook : write_hooks_[t.item]) {
      hook(t.item, t.old_value, get(t.item));
    }
  }
  return {};
}

bool ControlTable::touches_eeprom(std::uint16_t address, std::size_t length) const {
  for (std::size_t a = address; a < std::min(image_.size(), std::size_t{address} + length); ++a) {
    const int item = item_at_[a];
    if (item != kNoItem && spec_->items[static_cast<std::size_t>(item)].area == Area::Eeprom) {
      return true;
    }
  }
  return false;
}

std::size_t ControlTable::eeprom_bytes_holding(std::uint16_t address,
                                               std::span<const std::uint8_t> data) const {
  std::size_t holding = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::size_t a = address + i;
    holding += a < image_.size() && touches_eeprom(static_cast<std::uint16_t>(a), 1) &&
                       image_[a] == data[i]
                   ? 1
                   : 0;
  }
  return holding;
}

bool ControlTable::eeprom_locked() const {
  if (eeprom_lock_) {
    return eeprom_lock_();
  }
  if (spec_->traits().eeprom_locked_by_torque) {
    return torque_enable_ && get(*torque_enable_) != 0;
  }
  return lock_ && get(*lock_) != 0;
}

std::int64_t ControlTable::decode(const ItemSpec& item, std::span<const std::uint8_t> bytes) const {
  return decode_value(item, spec_->byte_order, bytes);
}

void ControlTable::encode(const ItemSpec& item, std::int64_t value,
                          std::span<std::uint8_t> out) const {
  encode_value(item, spec_->byte_order, value, out);
}

std::int64_t ControlTable::get(std::size_t item) const {
  const ItemSpec& spec = spec_->items.at(item);
  return decode(spec, std::span(image_).subspan(spec.address, spec.size));
}

std::int64_t ControlTable::get(std::string_view key) const {
  return get(index(key));
}

void ControlTable::set(std::size_t item, std::int64_t value) {
  const ItemSpec& spec = spec_->items.at(item);
  require_fits(spec, value);
  if (spec.area == Area::Eeprom && get(item) != value) {
    ++eeprom_changes_;
  }
  encode(spec, value, std::span(image_).subspan(spec.address, spec.size));
  // Only EEPROM items ask the lock: set() runs for every Present value on every tick.
  if (eeprom_keep_ && spec.area == Area::Eeprom) {
    keep_if_allowed(item, eeprom_keep_());
  }
}

void ControlTable::set(std::string_view key, std::int64_t value) {
  set(index(key), value);
}

void ControlTable::copy_from(std::size_t item, std::span<const std::uint8_t> image) {
  const ItemSpec& spec = spec_->items.at(item);
  const auto from = image.subspan(spec.address, spec.size);
  if (spec.area == Area::Eeprom &&
      !std::equal(from.begin(), from.end(), image_.begin() + spec.address)) {
    ++eeprom_changes_;
  }
  std::copy(from.begin(), from.end(), image_.begin() + spec.address);
  if (eeprom_keep_ && spec.area == Area::Eeprom) {
    keep_if_allowed(item, eeprom_keep_());
  }
}

std::size_t ControlTable::index(std::string_view key) const {
  const auto i = spec_->index_of(key);
  if (!i) {
    throw std::out_of_range(spec_->name + " has no item \"" + std::string(key) + "\"");
  }
  return *i;
}

void ControlTable::on_write(std::string_view key, WriteHook hook) {
  write_hooks_[index(key)].push_back(std::move(hook));
}

void ControlTable::add_validator(std::string_view key, Validator validator) {
  validators_[index(key)].push_back(std::move(validator));
}

void ControlTable::set_range_rule(std::string_view key, RangeRule rule) {
  range_rules_[index(key)] = std::move(rule);
}

std::uint64_t ControlTable::raw_value(std::size_t address, std::size_t size) const {
  constexpr std::size_t kMaxBytes = sizeof(std::uint64_t);
  if (size < 1 || size > kMaxBytes || address > image_.size() || size > image_.size() - address) {
    throw std::out_of_range("address " + std::to_string(address) + " size " + std::to_string(size) +
                            " is not 1 ~ 8 bytes within the " + std::to_string(image_.size()) +
                            "-byte table of " + spec_->name);
  }
  return unpack(spec_->byte_order, std::span(image_).subspan(address, size));
}

std::vector<std::uint8_t> ControlTable::encoded(std::size_t item, std::int64_t value) const {
  const ItemSpec& spec = spec_->items.at(item);
  require_fits(spec, value);
  std::vector<std::uint8_t> bytes(spec.size);
  encode(spec, value, bytes);
  return bytes;
}

bool ControlTable::fits(const ItemSpec& item, std::int64_t value) {
  const ItemRange range = representable_range(item);
  return value >= range.min && value <= range.max;
}

}  // namespace dxlemu::model
