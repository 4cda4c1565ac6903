#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "model/spec/model_spec.hpp"
#include "model/table/table_result.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::model {

/// The control table of one servo: a byte image in its model's byte order, initialised from it,
/// with the access rules of the e-Manual enforced on bus reads and writes, Indirect Address/Data,
/// and per-item write hooks through which behaviours and the motion model plug in: which ones an
/// item has is declared in one table, model/item_hooks.cpp. Rules and choices:
/// docs/control-table.md.
class ControlTable {
 public:
  /// Called after a bus write committed the item, with its old and new value.
  using WriteHook =
      std::function<void(std::size_t item, std::int64_t old_value, std::int64_t new_value)>;
  /// An extra rule for an item, checked with the built-in ones before anything is committed.
  using Validator = std::function<TableResult(std::size_t item, std::int64_t new_value)>;
  /// Says whether EEPROM items are locked now; replaces the family's rule (2XL430: both axes).
  using EepromLock = std::function<bool()>;
  /// Says whether an EEPROM change made now is kept over power-off (FEETECH: Lock flag 0).
  using EepromKeep = std::function<bool()>;
  /// The range an item accepts now when it depends on a mode (Goal Position in Extended Position
  /// Control Mode); nullopt keeps the item's static range and limit items.
  using RangeRule = std::function<std::optional<ItemRange>(std::size_t item)>;

  /// A table for `spec` with every item at its initial value and the hooks of the item hook table
  /// that need nothing but the table installed (its family's rules: item_hooks.hpp). Throws
  /// std::invalid_argument for an item wider than 8 bytes.
  explicit ControlTable(std::shared_ptr<const ModelSpec> spec);

  /// The model this table belongs to.
  const ModelSpec& spec() const { return *spec_; }

  /// Power-on or reboot: RAM items (and EEPROM items too when `eeprom` is true, as a factory reset
  /// does) return to their initial values, Hybrid items to their saved values (with `eeprom`, to
  /// their initial values, which become the saved ones). No hooks run.
  void load_initial(bool eeprom);

  /// Hybrid Save: the Hybrid items' present values become the ones power-on and reboot restore.
  void save_hybrid();

  /// True while a Hybrid item differs from its saved value.
  bool hybrid_changed() const;

  /// The value a reboot restores to Hybrid item `item` (the last saved one).
  std::int64_t hybrid_saved(std::size_t item) const { return hybrid_saved_.at(item); }

  /// Device side: Hybrid item `item` holds `value`, saved (a state file restored at start).
  void restore_hybrid(std::size_t item, std::int64_t value);

  /// From now on an EEPROM change is kept over power-off only while `keep` says so; a reboot
  /// (load_initial(false)) brings every EEPROM item back to its last kept value. Without it,
  /// every EEPROM change is kept (DYNAMIXEL).
  void set_eeprom_keep(EepromKeep keep);

  /// The value item `item` has after a power cycle: a Hybrid item's saved value, an EEPROM
  /// item's last kept one (set_eeprom_keep), else its present value. What a state file keeps.
  std::int64_t kept_value(std::size_t item) const;

  /// Device side: EEPROM or Hybrid item `item` holds `value`, kept over power-off (a state file
  /// restored at start).
  void restore_kept(std::size_t item, std::int64_t value);

  /// A bus Read: `length` bytes from `address` into `out`. Reserved bytes between items read as 0
  /// and a read may start or end inside an item; a read past the end of the table is an Access
  /// error and yields no data (protocol2.md "Read"). Indirect Data reads the mapped address.
  /// Nothing runs on a read: every value a read shows is in the image already (the motion model
  /// publishes its Present values when they change).
  TableResult bus_read(std::uint16_t address, std::uint16_t length,
                       std::vector<std::uint8_t>& out) const;
  /// As bus_read, under the rules of `protocol`: where it addresses registers (Modbus RTU), a
  /// register whose bytes all belong to items the protocol leaves out is an Access error, and a
  /// byte of such an item beside another reads 0 (docs/modbus.md "The register map").
  TableResult bus_read(std::uint16_t address, std::uint16_t length, std::vector<std::uint8_t>& out,
                       wire::Protocol protocol) const;

  /// A bus Write of `data` from `address` under the rules of `protocol`. Every touched item is
  /// validated first (defined, writable, EEPROM unlocked, whole item in 2.0, range, limit,
  /// validators); only then is anything written, so a refused write changes nothing. Write hooks
  /// run after the commit, in address order. Allocates nothing once the table has seen a write
  /// as long as the one before (unless refused: the reason is a string). Hooks must not start
  /// another bus write on the same table (checked: std::logic_error).
  TableResult bus_write(std::uint16_t address, std::span<const std::uint8_t> data,
                        wire::Protocol protocol);

  /// Calls `f(item)` with the index of each item the last successful bus_write wrote, in index
  /// order. Only right after that bus_write: the next check_write or bus_write replaces them.
  template <class F>
  void for_each_written(F&& f) const {
    for (const Touched& t : touched_) {
      f(t.item);
    }
  }

  /// What bus_write would answer, without writing (Reg Write checks its data when it arrives).
  TableResult check_write(std::uint16_t address, std::span<const std::uint8_t> data,
                          wire::Protocol protocol) const;

  /// True when any of `length` bytes from `address` belongs to an EEPROM item.
  bool touches_eeprom(std::uint16_t address, std::size_t length) const;

  /// How many of the bytes of `data`, written from `address`, are EEPROM bytes that now hold
  /// what was written (a refused write leaves them as they were: they count only if equal).
  std::size_t eeprom_bytes_holding(std::uint16_t address, std::span<const std::uint8_t> data) const;

  /// Device side: the value of an item, bypassing hooks.
  std::int64_t get(std::size_t item) const;
  /// Device side: the value of the item with `key`. Throws std::out_of_range for an unknown key.
  std::int64_t get(std::string_view key) const;
  /// Device side: sets an item, bypassing access rules and hooks (the motion model, the control
  /// API). Throws std::invalid_argument if the value does not fit the item's size.
  void set(std::size_t item, std::int64_t value);
  /// As set(item, value), by key. Throws std::out_of_range for an unknown key.
  void set(std::string_view key, std::int64_t value);

  /// Device side: copies the item's bytes from `image`, another byte image of this model (a
  /// Control Table Backup). Bypasses access rules and hooks.
  void copy_from(std::size_t item, std::span<const std::uint8_t> image);

  /// Index of the item with `key`. Throws std::out_of_range for an unknown key.
  std::size_t index(std::string_view key) const;

  /// The raw byte image (address 0 up to the end of the last item).
  std::span<const std::uint8_t> bytes() const { return image_; }

  /// Registers a write hook or a rule for an item (several per item run in registration order).
  /// The emulator's own are declared in model/item_hooks.cpp and installed from there; these
  /// calls are how that table plugs in (and how tests watch a table).
  void on_write(std::string_view key, WriteHook hook);
  void add_validator(std::string_view key, Validator validator);
  /// Lets `rule` replace the item's static range and limit items (one rule per item; a later one
  /// replaces it). Validators still run.
  void set_range_rule(std::string_view key, RangeRule rule);
  /// Replaces the family's EEPROM lock rule (torque on, or 1.0 Lock) with `lock`.
  void set_eeprom_lock(EepromLock lock) { eeprom_lock_ = std::move(lock); }

  /// True while EEPROM items refuse bus writes.
  bool eeprom_locked() const;

  /// Device side: the `size` bytes from `address` as one unsigned number in the model's byte
  /// order (as on the wire), straight from the image: no access rules, read hooks or Indirect
  /// Data mapping.
  /// Throws std::out_of_range when they are not all inside the table or `size` is not 1 ~ 8.
  std::uint64_t raw_value(std::size_t address, std::size_t size) const;

  /// The item's bytes holding `value`, as a bus Write of that item would carry them. Throws
  /// std::invalid_argument, as set() does, if the value does not fit the item's size.
  std::vector<std::uint8_t> encoded(std::size_t item, std::int64_t value) const;

  /// True when `value` fits `item`'s size and encoding (representable_range(), item_encoding.hpp):
  /// what set() and encoded() accept.
  static bool fits(const ItemSpec& item, std::int64_t value);

  /// How many times an EEPROM byte or a saved Hybrid value has changed since the table was made
  /// (by a bus write, a device-side set, a copy or a Hybrid Save): equal counts mean unchanged
  /// non-volatile memory, without comparing it.
  std::uint64_t eeprom_changes() const { return eeprom_changes_; }

 private:
  /// The widest item a table holds: its value is one std::int64_t.
  static constexpr std::size_t kMaxItemBytes = sizeof(std::int64_t);

  struct Touched {
    std::size_t item = 0;
    std::array<std::uint8_t, kMaxItemBytes> bytes{};  // the item's bytes after the write
    std::size_t covered = 0;                          // how many of them the write supplies
    std::int64_t old_value = 0;                       // set when the write is committed
  };

  /// Fills touched_ with the items `data` written from `address` touches, by item index. Where
  /// `protocol` addresses registers, a byte it cannot write is skipped beside one it can.
  TableResult plan_write(std::uint16_t address, std::span<const std::uint8_t> data,
                         wire::Protocol protocol) const;
  // The register map (register_map.cpp).
  /// True when the byte at `address` belongs to an item `protocol` leaves out.
  bool absent(std::size_t address, wire::Protocol protocol) const;
  /// True when a write in `protocol` can reach the byte at `address`: an item it has, writable.
  bool takes_write(std::size_t address, wire::Protocol protocol) const;
  /// For a write of `length` bytes from `first` in `protocol`: true when the byte at `address`
  /// is to be skipped (another byte of its register, inside the write, takes it); an Access
  /// refusal when no byte of its register can be written; nullopt to write it.
  std::optional<TableResult> skip_in_register(std::size_t address, std::size_t first,
                                              std::size_t length, wire::Protocol protocol) const;
  /// The ID range `protocol` allows: a write of another ID is refused as out of range.
  TableResult check_id(std::size_t item, std::int64_t value, wire::Protocol protocol) const;
  TableResult validate(const std::vector<Touched>& touched, wire::Protocol protocol) const;
  /// Records EEPROM item `item`'s present value as kept when `keep` (with set_eeprom_keep).
  void keep_if_allowed(std::size_t item, bool keep);
  TableResult check_static_range(const ItemSpec& item, std::int64_t value,
                                 const std::vector<Touched>& touched) const;
  std::optional<std::uint16_t> resolve(std::uint16_t address) const;
  std::int64_t decode(const ItemSpec& item, std::span<const std::uint8_t> bytes) const;
  void encode(const ItemSpec& item, std::int64_t value, std::span<std::uint8_t> out) const;
  std::int64_t value_after(std::size_t item, const std::vector<Touched>& touched) const;

  std::shared_ptr<const ModelSpec> spec_;
  std::vector<std::uint8_t> image_;
  std::vector<std::int64_t> hybrid_saved_;  // item -> saved value (Hybrid items only)
  EepromKeep eeprom_keep_;                  // empty: every EEPROM change is kept
  std::vector<std::int64_t> eeprom_kept_;   // item -> kept value (EEPROM, with eeprom_keep_)
  std::vector<int> item_at_;                // address -> item index, -1 for reserved bytes
  std::vector<int> indirect_address_;       // address -> item index of its Indirect Address, or -1
  std::vector<std::vector<WriteHook>> write_hooks_;
  std::vector<std::vector<Validator>> validators_;
  std::vector<RangeRule> range_rules_;
  EepromLock eeprom_lock_;
  std::optional<std::size_t> torque_enable_;
  std::optional<std::size_t> lock_;
  std::optional<std::size_t> id_;
  std::uint64_t eeprom_changes_ = 0;
  // The items of the write being planned, checked or committed: kept between writes so that a
  // write allocates nothing once one as long has been seen (Sync Write reaches every servo).
  mutable std::vector<Touched> touched_;
  bool running_hooks_ = false;  // a write's hooks are running: touched_ is in use
};

}  // namespace dxlemu::model
