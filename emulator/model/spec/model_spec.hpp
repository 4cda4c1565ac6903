#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "model/spec/family_traits.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::model {

/// Where an item lives: EEPROM keeps its value across power cycles and is write-locked while
/// torque is on; RAM returns to its initial value at power-on. Hybrid (DYNAMIXEL-Y) is written
/// like RAM, torque on or off, and returns at power-on to the values last saved through Hybrid
/// Save(170) (docs/families.md "DYNAMIXEL-Y").
enum class Area { Eeprom, Ram, Hybrid };

/// Volts per unit of a voltage item whose unit names none (every 0.1 V page).
inline constexpr double kDefaultVoltageUnitV = 0.1;

/// The figure a unit string starts with ("0.01 [V]" -> 0.01, "about 0.229 [rev/min]" ->
/// 0.229), or nullopt when it starts with none.
std::optional<double> unit_figure(std::string_view unit);

/// How a multi-byte item's bytes are ordered in the table, and so on the wire: the lowest byte at
/// the item's address (every DYNAMIXEL; FEETECH STS, SMS, HLS) or the highest (FEETECH SCS).
enum class ByteOrder { Little, Big };

/// Whether the bus may write an item.
enum class Access { ReadOnly, ReadWrite };

/// Another item bounding an item's value (e.g. Goal Position within Max Position Limit), possibly
/// negated (Goal PWM >= -PWM Limit).
struct ItemBound {
  std::size_t item = 0;  ///< index into ModelSpec::items
  bool negate = false;
};

/// An inclusive range of item values.
struct ItemRange {
  std::int64_t min = 0;
  std::int64_t max = 0;
};

/// One control-table item as the model file describes it.
struct ItemSpec {
  std::string key;   ///< snake_case of the e-Manual name, unique per model
  std::string name;  ///< the e-Manual name
  std::uint16_t address = 0;
  std::uint8_t size = 1;  ///< bytes: 1, 2 or 4
  Access access = Access::ReadWrite;
  Area area = Area::Ram;
  bool is_signed = false;  ///< two's complement
  /// Sign-magnitude instead: this bit is the sign (set: negative), the bits below it the
  /// magnitude (FEETECH "BIT15 is the direction bit"). Never together with is_signed.
  std::optional<std::uint8_t> sign_bit;
  std::int64_t initial = 0;
  std::optional<std::size_t> initial_from;  ///< copy this item's value at power-on instead
  std::int64_t min = 0;                     ///< static range: Data Range Error outside
  std::int64_t max = 0;
  std::vector<std::int64_t> values;    ///< when not empty: the only accepted values
  std::optional<ItemBound> limit_min;  ///< dynamic limits: Data Limit Error beyond
  std::optional<ItemBound> limit_max;
  std::string unit;
  /// The protocols whose map leaves this item out (the page prints "N/A" in their address
  /// column: Return Delay Time in Modbus RTU): while a servo speaks one, the item is neither
  /// read nor written through it and has no effect (docs/modbus.md).
  std::vector<wire::Protocol> absent_in;

  /// True unless `protocol` leaves the item out (absent_in).
  bool present_in(wire::Protocol protocol) const {
    return std::find(absent_in.begin(), absent_in.end(), protocol) == absent_in.end();
  }

  /// One past the item's last byte.
  std::size_t end() const { return std::size_t{address} + size; }
  /// True when `value` is in the static range and, if listed, among `values`.
  bool in_range(std::int64_t value) const;
};

/// An Indirect Address/Data block: Indirect Data `data + i` behaves as the control-table address
/// held in the 2-byte item at `address + 2 * i`, for i < count
/// (includes/control_table_indirect_data.md).
struct IndirectBlock {
  std::uint16_t address = 0;
  std::uint16_t data = 0;
  std::uint16_t count = 0;
};

/// Another firmware of the same model whose control table differs (the XL330/XC330 pages: "Firmware
/// versions prior to V53 support up to 20 Indirect Address/Data items"). It states only what
/// differs; everything else is the model's. model_for_firmware() (firmware_variant.hpp) builds it.
struct FirmwareVariant {
  std::uint8_t firmware_version = 0;
  /// Replaces ModelSpec::indirect, and with it the Indirect Address/Data items.
  std::vector<IndirectBlock> indirect;
  std::vector<std::string> notes;  ///< why it exists and what it changes, citing the page
};

/// One Baud Rate item value and the bit rate it selects.
struct BaudRate {
  std::int64_t index = 0;
  std::uint32_t bps = 0;
};

/// Processing time before a reply starts, per instruction kind (microseconds), and the silence
/// after Reboot or power-on (milliseconds).
struct Timing {
  std::uint32_t ping_us = 0;
  std::uint32_t read_us = 0;
  std::uint32_t write_us = 0;
  std::uint32_t write_per_byte_us = 0;
  std::uint32_t boot_ms = 0;
};

/// Parameters of the motion model. Optional figures are absent when no source stated them.
struct MotionSpec {
  double degrees_per_pulse = 0;
  double velocity_unit_rpm = 0;
  std::optional<double> current_unit_ma;
  std::optional<double> no_load_speed_rpm;  ///< at nominal_voltage_v
  std::optional<double> stall_torque_nm;    ///< at nominal_voltage_v
  /// The input voltage at which no_load_speed_rpm, stall_torque_nm and stall_current_a are stated.
  std::optional<double> nominal_voltage_v;
  std::optional<double> stall_current_a;         ///< at nominal_voltage_v
  std::optional<double> acceleration_unit_rpm2;  ///< rev/min² per unit of Profile Acceleration
  /// What the model's current reading (Present Current; MX 1.0 Current, EX-106+ Sensed Current)
  /// shows at 0 A: 2048 on MX 1.0, 512 on EX-106+, 0 elsewhere. The reading is this plus the
  /// current in units of current_unit_ma.
  std::int64_t current_zero = 0;
};

/// Hashes item keys given as std::string or std::string_view alike, so that lookups by
/// std::string_view make no copy.
struct KeyHash {
  using is_transparent = void;  ///< enables heterogeneous lookup
  std::size_t operator()(std::string_view key) const { return std::hash<std::string_view>{}(key); }
};

/// Everything the emulator knows about one model (DYNAMIXEL or FEETECH), loaded from its model
/// file.
struct ModelSpec {
  std::string name;   ///< e.g. "xm430-w350": the name used in the CLI, configs and the API
  std::string title;  ///< e.g. "XM430-W350"
  std::uint16_t model_number = 0;
  /// The model whose number this one reports too, where ROBOTIS gave two products one number
  /// (XC430-T150BB reports XC430-W150's 1070); empty for the usual one number, one model.
  std::string shares_model_number_with;
  std::uint8_t firmware_version = 0;
  Family family = Family::X;              ///< its traits: traits()
  std::vector<wire::Protocol> protocols;  ///< default first
  /// True when the model speaks `protocol` (lists it in `protocols`).
  bool speaks(wire::Protocol protocol) const {
    return std::find(protocols.begin(), protocols.end(), protocol) != protocols.end();
  }
  std::uint8_t default_id = 1;
  std::vector<BaudRate> baud_rates;
  std::int64_t default_baud_index = 0;
  std::uint32_t return_delay_unit_us = 2;
  ByteOrder byte_order = ByteOrder::Little;  ///< of every multi-byte item
  Timing timing;
  MotionSpec motion;
  std::vector<IndirectBlock> indirect;
  /// The other firmware it may run, besides firmware_version (the default: what a buyer gets).
  std::vector<FirmwareVariant> firmware_variants;
  std::uint8_t axes = 1;
  std::vector<std::string> shared_items;
  std::string source;
  std::vector<std::string> notes;
  std::vector<ItemSpec> items;  ///< in address order
  /// The model file's `refusal_bits`, replacing its family's refusals (FEETECH models only).
  std::optional<Refusals> refusal_bits;
  /// Key → index into `items`, for find() and index_of(): servos look up dozens of items by key
  /// when they are built. Filled by index_items().
  std::unordered_map<std::string, std::size_t, KeyHash, std::equal_to<>> item_index;

  /// What the model's family does beyond its control table (family_traits.hpp).
  const FamilyTraits& traits() const { return traits_of(family); }
  /// Who makes the model (its family's maker).
  Maker maker() const { return traits().maker; }
  /// What the servo answers to the refusals FEETECH gives no error bit: the file's, else the
  /// family's.
  Refusals refusals() const { return refusal_bits.value_or(traits().refusals); }
  /// Fills item_index from `items`; call it whenever `items` is set (the loader does).
  void index_items();
  /// The item with `key`, or nullptr.
  const ItemSpec* find(std::string_view key) const;
  /// Index of the item with `key`, or nullopt. Throws std::logic_error if index_items() was not
  /// called after `items` was set.
  std::optional<std::size_t> index_of(std::string_view key) const;
  /// One past the highest address of any item: the size of the control table's byte image.
  std::size_t table_size() const;
  /// The bit rate of a Baud Rate item value, or nullopt if the model does not offer it.
  std::optional<std::uint32_t> bps_for_index(std::int64_t index) const;
};

}  // namespace dxlemu::model
