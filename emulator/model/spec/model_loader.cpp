#include "model/spec/model_loader.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "model/spec/firmware_variant.hpp"
#include "model/spec/json_node.hpp"
#include "model/spec/shared_fields.hpp"
#include "model/table/item_encoding.hpp"

namespace dxlemu::model {
namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 23> kModelFields = {"$schema",
                                                           "name",
                                                           "title",
                                                           "model_number",
                                                           "shares_model_number_with",
                                                           "firmware_version",
                                                           "family",
                                                           "protocols",
                                                           "default_id",
                                                           "baud_rates",
                                                           "default_baud_index",
                                                           "return_delay_unit_us",
                                                           "byte_order",
                                                           "timing",
                                                           "motion",
                                                           "indirect",
                                                           "firmware_variants",
                                                           "axes",
                                                           "shared_items",
                                                           "source",
                                                           "notes",
                                                           "refusal_bits",
                                                           "items"};
constexpr std::array<std::string_view, 18> kItemFields = {
    "key",     "name",         "address",   "size",     "access",    "area",
    "initial", "initial_from", "signed",    "sign_bit", "min",       "max",
    "values",  "limit_min",    "limit_max", "unit",     "absent_in", "note"};
constexpr std::array<std::string_view, 2> kBaudFields = {"index", "bps"};
constexpr std::array<std::string_view, 5> kTimingFields = {"ping_us", "read_us", "write_us",
                                                           "write_per_byte_us", "boot_ms"};
constexpr std::array<std::string_view, 9> kMotionFields = {
    "degrees_per_pulse", "velocity_unit_rpm",      "current_unit_ma",
    "no_load_speed_rpm", "stall_torque_nm",        "nominal_voltage_v",
    "stall_current_a",   "acceleration_unit_rpm2", "current_zero"};
// The members of `refusal_bits`, one per class of refusal (docs/model-format.md).
struct RefusalField {
  const char* key;
  wire::RefusalAnswer Refusals::*answer;
};
constexpr std::array<RefusalField, 4> kRefusalClasses = {{{"checksum", &Refusals::checksum},
                                                          {"instruction", &Refusals::instruction},
                                                          {"read", &Refusals::read},
                                                          {"range", &Refusals::range}}};
constexpr std::array<std::string_view, kRefusalClasses.size()> kRefusalFields = [] {
  std::array<std::string_view, kRefusalClasses.size()> keys{};
  for (std::size_t i = 0; i < keys.size(); ++i) {
    keys[i] = kRefusalClasses[i].key;
  }
  return keys;
}();
constexpr std::string_view kSilent = "silent";
constexpr std::array<std::string_view, 3> kIndirectFields = {"address", "data", "count"};
constexpr std::array<std::string_view, 3> kVariantFields = {"firmware_version", "indirect",
                                                            "notes"};

constexpr std::int64_t kU8 = 0xFF;
constexpr std::int64_t kU16 = 0xFFFF;
constexpr std::int64_t kU32 = 0xFFFFFFFF;

bool is_snake_case(const std::string& key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// A sign-magnitude item's sign bit: inside the item, with at least one magnitude bit below it.
std::uint8_t read_sign_bit(const JsonNode& n, const ItemSpec& s) {
  const JsonNode bit = n.child("sign_bit");
  if (s.is_signed) {
    bit.fail(
        "cannot be given with \"signed\": true (sign-magnitude or two's complement, not both)");
  }
  const int top = 8 * s.size - 1;
  const std::int64_t value = bit.integer(0, kU8);
  if (value < 1 || value > top) {
    bit.fail("must be 1 ~ " + std::to_string(top) + " for a " + std::to_string(s.size) +
             "-byte item, got " + std::to_string(value));
  }
  return static_cast<std::uint8_t>(value);
}

// One class's answer: "silent" (no status), or the bit its status carries. FEETECH defines the
// status bits 0, 1, 2, 3 and 5 (voltage, angle sensor, temperature, current, load): a refusal
// bit may only be one of the others, or a client would take the refusal for a hardware error.
wire::RefusalAnswer read_refusal_answer(const JsonNode& n) {
  if (n.is_string()) {
    const std::string word = n.string();
    if (word != kSilent) {
      n.fail("must be \"silent\" or a status bit, got \"" + word + "\"");
    }
    return wire::kSilentRefusal;
  }
  if (!n.is_integer()) {
    n.fail("must be \"silent\" or a status bit (an integer 0 ~ 255)");
  }
  const auto bit = static_cast<std::uint8_t>(n.integer(0, kU8));
  if ((bit & wire::feetech_error::kDefinedBits) != 0) {
    n.fail("uses a bit FEETECH defines for a hardware error (1, 2, 4, 8, 32 are taken)");
  }
  return {.silent = false, .bit = bit};
}

// The classes a model file names replace its family's; the others stay the family's.
Refusals read_refusals(const JsonNode& n, const ModelSpec& spec) {
  n.expect_object(kRefusalFields);
  if (spec.maker() != Maker::Feetech) {
    n.fail("is a setting of FEETECH models only");
  }
  Refusals out = spec.traits().refusals;
  for (const RefusalField& field : kRefusalClasses) {
    if (n.has(field.key)) {
      out.*field.answer = read_refusal_answer(n.child(field.key));
    }
  }
  return out;
}

ByteOrder read_byte_order(const JsonNode& n) {
  const std::string order = n.string();
  if (order == "little") {
    return ByteOrder::Little;
  }
  if (order != "big") {
    n.fail("must be \"little\" or \"big\", got \"" + order + "\"");
  }
  return ByteOrder::Big;
}

// Bounds and initial_from name other items; they are resolved once every item is known.
struct PendingItem {
  ItemSpec spec;
  std::string pointer;
  std::optional<std::string> initial_from;
  std::optional<std::string> limit_min;
  std::optional<std::string> limit_max;
  bool has_initial = false;
};

// `protocols`: the model's, which `absent_in` may name (some of them).
PendingItem read_item(const JsonNode& n, const std::vector<wire::Protocol>& protocols) {
  n.expect_object(kItemFields);
  PendingItem p;
  p.pointer = n.pointer();
  ItemSpec& s = p.spec;
  s.key = n.at("key").string();
  if (!is_snake_case(s.key)) {
    n.at("key").fail("must be snake_case (a-z, 0-9, _), got \"" + s.key + "\"");
  }
  s.name = n.at("name").string();
  s.address = static_cast<std::uint16_t>(n.at("address").integer(0, kU16));
  const std::int64_t size = n.at("size").integer(0, kU8);
  if (size != 1 && size != 2 && size != 4) {
    n.at("size").fail("must be 1, 2 or 4, got " + std::to_string(size));
  }
  s.size = static_cast<std::uint8_t>(size);
  const std::string access = n.at("access").string();
  if (access != "R" && access != "RW") {
    n.at("access").fail("must be \"R\" or \"RW\", got \"" + access + "\"");
  }
  s.access = access == "R" ? Access::ReadOnly : Access::ReadWrite;
  const std::string area = n.at("area").string();
  if (area == "EEPROM") {
    s.area = Area::Eeprom;
  } else if (area == "RAM") {
    s.area = Area::Ram;
  } else if (area == "Hybrid") {
    s.area = Area::Hybrid;
  } else {
    n.at("area").fail("must be \"EEPROM\", \"RAM\" or \"Hybrid\", got \"" + area + "\"");
  }
  s.is_signed = n.has("signed") && n.child("signed").boolean();
  if (n.has("sign_bit")) {
    s.sign_bit = read_sign_bit(n, s);
  }
  const auto [lo, hi] = representable_range(s);
  s.min = n.has("min") ? n.child("min").integer(lo, hi) : lo;
  s.max = n.has("max") ? n.child("max").integer(lo, hi) : hi;
  if (s.min > s.max) {
    n.child("max").fail("is below min (" + std::to_string(s.min) + ")");
  }
  if (n.has("values")) {
    const JsonNode values = n.child("values");
    for (std::size_t i = 0, count = values.array_size(); i < count; ++i) {
      s.values.push_back(values.at(i).integer(s.min, s.max));
    }
    if (s.values.empty()) {
      values.fail("must list at least one value");
    }
  }
  if (n.has("initial") == n.has("initial_from")) {
    n.fail("needs exactly one of \"initial\" and \"initial_from\"");
  }
  if (n.has("initial")) {
    p.has_initial = true;
    s.initial = n.child("initial").integer(lo, hi);
    if (!s.in_range(s.initial)) {
      n.child("initial").fail("value " + std::to_string(s.initial) +
                              " is outside the item's range");
    }
  } else {
    p.initial_from = n.child("initial_from").string();
  }
  if (n.has("limit_min")) {
    p.limit_min = n.child("limit_min").string();
  }
  if (n.has("limit_max")) {
    p.limit_max = n.child("limit_max").string();
  }
  if (n.has("unit")) {
    s.unit = n.child("unit").string();
  }
  if (n.has("absent_in")) {
    s.absent_in = read_absent_in(n.child("absent_in"), protocols);
  }
  if (n.has("note")) {
    n.child("note").string();
  }
  return p;
}

std::vector<ItemSpec> read_items(const JsonNode& items_node,
                                 const std::vector<wire::Protocol>& protocols) {
  std::vector<PendingItem> pending;
  for (std::size_t i = 0, n = items_node.array_size(); i < n; ++i) {
    pending.push_back(read_item(items_node.at(i), protocols));
  }
  if (pending.empty()) {
    items_node.fail("must list at least one item");
  }
  std::map<std::string, std::size_t> by_key;
  std::map<std::uint16_t, std::size_t> by_address;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const ItemSpec& s = pending[i].spec;
    const JsonNode n = items_node.at(i);
    if (const auto [it, fresh] = by_key.emplace(s.key, i); !fresh) {
      n.at("key").fail("duplicate key \"" + s.key + "\" (also " + pending[it->second].pointer +
                       ")");
    }
    if (const auto [it, fresh] = by_address.emplace(s.address, i); !fresh) {
      n.at("address").fail("duplicate address " + std::to_string(s.address) + " (also " +
                           pending[it->second].pointer + ")");
    }
  }
  // Overlap: in address order, each item must end before the next begins.
  for (auto it = by_address.begin(); std::next(it) != by_address.end(); ++it) {
    const ItemSpec& a = pending[it->second].spec;
    const auto& [next_address, next_index] = *std::next(it);
    if (a.end() > next_address) {
      items_node.at(next_index)
          .at("address")
          .fail("overlaps " + pending[it->second].pointer + " (\"" + a.key + "\", addresses " +
                std::to_string(a.address) + ".." + std::to_string(a.end() - 1) + ")");
    }
  }

  // Items end up in address order; references become indices into that order.
  std::map<std::string, std::size_t> sorted_index;
  std::size_t next = 0;
  for (const auto& [address, i] : by_address) {
    sorted_index[pending[i].spec.key] = next++;
  }
  auto resolve = [&](std::size_t i, const char* field, const std::string& ref) {
    const bool negate = !ref.empty() && ref.front() == '-';
    const std::string key = negate ? ref.substr(1) : ref;
    const auto found = sorted_index.find(key);
    if (found == sorted_index.end()) {
      items_node.at(i).at(field).fail("names an unknown item \"" + key + "\"");
    }
    return ItemBound{found->second, negate};
  };
  std::vector<ItemSpec> items;
  items.reserve(pending.size());
  for (const auto& [address, i] : by_address) {
    PendingItem& p = pending[i];
    if (p.initial_from) {
      const ItemBound from = resolve(i, "initial_from", *p.initial_from);
      if (from.negate) {
        items_node.at(i).at("initial_from").fail("cannot be negated");
      }
      p.spec.initial_from = from.item;
    }
    if (p.limit_min) {
      p.spec.limit_min = resolve(i, "limit_min", *p.limit_min);
    }
    if (p.limit_max) {
      p.spec.limit_max = resolve(i, "limit_max", *p.limit_max);
    }
    items.push_back(std::move(p.spec));
  }
  // An initial value copied from another item must fit this item's range.
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].initial_from) {
      const ItemSpec& from = items[*items[i].initial_from];
      if (from.initial_from || !items[i].in_range(from.initial)) {
        items_node.at(by_address.at(items[i].address))
            .at("initial_from")
            .fail("\"" + from.key + "\" starts at " + std::to_string(from.initial) +
                  ", outside this item's range");
      }
      items[i].initial = from.initial;
    }
  }
  return items;
}

// Every indirect block must be backed by its items: 2-byte address items and 1-byte data items.
void check_indirect(const JsonNode& n, const ModelSpec& spec) {
  auto item_at = [&](std::uint16_t address) -> const ItemSpec* {
    for (const ItemSpec& item : spec.items) {
      if (item.address == address) {
        return &item;
      }
    }
    return nullptr;
  };
  for (std::size_t b = 0; b < spec.indirect.size(); ++b) {
    const IndirectBlock& block = spec.indirect[b];
    for (std::uint16_t i = 0; i < block.count; ++i) {
      const auto address = static_cast<std::uint16_t>(block.address + 2 * i);
      const auto data = static_cast<std::uint16_t>(block.data + i);
      const ItemSpec* a = item_at(address);
      const ItemSpec* d = item_at(data);
      if (a == nullptr || a->size != 2 || d == nullptr || d->size != 1) {
        n.at(b).fail("entry " + std::to_string(i) + " needs a 2-byte item at " +
                     std::to_string(address) + " and a 1-byte item at " + std::to_string(data));
      }
    }
  }
}

std::vector<IndirectBlock> read_indirect(const JsonNode& blocks) {
  std::vector<IndirectBlock> out;
  for (std::size_t i = 0, n = blocks.array_size(); i < n; ++i) {
    const JsonNode b = blocks.at(i);
    b.expect_object(kIndirectFields);
    out.push_back({static_cast<std::uint16_t>(b.at("address").integer(0, kU16)),
                   static_cast<std::uint16_t>(b.at("data").integer(0, kU16)),
                   static_cast<std::uint16_t>(b.at("count").integer(1, kU16))});
  }
  if (out.empty()) {
    blocks.fail("must list at least one block");
  }
  return out;
}

}  // namespace

ModelSpec model_from_json(const json& document, const std::string& origin) {
  const JsonNode root(document, "", origin);
  root.expect_object(kModelFields);
  ModelSpec spec;
  spec.name = root.at("name").string();
  spec.title = root.at("title").string();
  spec.model_number = static_cast<std::uint16_t>(root.at("model_number").integer(0, kU16));
  if (root.has("shares_model_number_with")) {
    spec.shares_model_number_with = root.child("shares_model_number_with").string();
  }
  spec.firmware_version = static_cast<std::uint8_t>(root.at("firmware_version").integer(0, kU8));
  spec.family = read_family(root.at("family"));
  spec.protocols = read_protocols(root.at("protocols"), spec.family);
  spec.default_id =
      static_cast<std::uint8_t>(root.at("default_id").integer(0, wire::highest_unicast_id()));

  const JsonNode bauds = root.at("baud_rates");
  for (std::size_t i = 0, n = bauds.array_size(); i < n; ++i) {
    const JsonNode b = bauds.at(i);
    b.expect_object(kBaudFields);
    const BaudRate rate{b.at("index").integer(0, kU32),
                        static_cast<std::uint32_t>(b.at("bps").integer(1, kU32))};
    if (spec.bps_for_index(rate.index)) {
      b.at("index").fail("lists index " + std::to_string(rate.index) + " twice");
    }
    spec.baud_rates.push_back(rate);
  }
  spec.default_baud_index = root.at("default_baud_index").integer(0, kU32);
  if (!spec.bps_for_index(spec.default_baud_index)) {
    root.at("default_baud_index").fail("is not an index of baud_rates");
  }
  spec.return_delay_unit_us =
      static_cast<std::uint32_t>(root.at("return_delay_unit_us").integer(1, kU16));
  if (root.has("byte_order")) {
    spec.byte_order = read_byte_order(root.child("byte_order"));
  }

  const JsonNode timing = root.at("timing");
  timing.expect_object(kTimingFields);
  auto micros = [&](const char* key) {
    return static_cast<std::uint32_t>(timing.at(key).integer(0, kU32));
  };
  spec.timing = {micros("ping_us"), micros("read_us"), micros("write_us"),
                 micros("write_per_byte_us"), micros("boot_ms")};

  const JsonNode motion = root.at("motion");
  motion.expect_object(kMotionFields);
  spec.motion.degrees_per_pulse = motion.at("degrees_per_pulse").positive_number();
  spec.motion.velocity_unit_rpm = motion.at("velocity_unit_rpm").positive_number();
  auto optional_number = [&](const char* key) -> std::optional<double> {
    return motion.has(key) ? std::optional(motion.child(key).positive_number()) : std::nullopt;
  };
  spec.motion.current_unit_ma = optional_number("current_unit_ma");
  spec.motion.no_load_speed_rpm = optional_number("no_load_speed_rpm");
  spec.motion.stall_torque_nm = optional_number("stall_torque_nm");
  spec.motion.nominal_voltage_v = optional_number("nominal_voltage_v");
  spec.motion.stall_current_a = optional_number("stall_current_a");
  spec.motion.acceleration_unit_rpm2 = optional_number("acceleration_unit_rpm2");
  if (motion.has("current_zero")) {
    spec.motion.current_zero = motion.child("current_zero").integer(0, kU32);
  }

  spec.source = root.at("source").string();
  if (root.has("notes")) {
    spec.notes = root.child("notes").strings();
  }
  spec.items = read_items(root.at("items"), spec.protocols);
  spec.index_items();
  // Every servo needs these to be on a bus at all: its address, its line speed and its reply
  // timing (model::Servo reads them when it is built). Every DYNAMIXEL table has Return Delay
  // Time; FEETECH's HLS table has none (its address 7 is the Secondary ID): it answers without.
  for (const std::string key : {"id", "baud_rate", "return_delay_time"}) {
    if (key == "return_delay_time" && spec.maker() == Maker::Feetech) {
      continue;
    }
    if (!spec.find(key)) {
      root.at("items").fail("has no item \"" + key +
                            "\" (every model needs id, baud_rate and return_delay_time; a "
                            "FEETECH model may lack return_delay_time)");
    }
  }
  if (root.has("refusal_bits")) {
    spec.refusal_bits = read_refusals(root.child("refusal_bits"), spec);
  }

  if (root.has("indirect")) {
    const JsonNode blocks = root.child("indirect");
    spec.indirect = read_indirect(blocks);
    check_indirect(blocks, spec);
  }
  if (root.has("axes")) {
    spec.axes = static_cast<std::uint8_t>(root.child("axes").integer(1, 2));
  }
  if (root.has("shared_items")) {
    const JsonNode shared = root.child("shared_items");
    spec.shared_items = shared.strings();
    for (std::size_t i = 0; i < spec.shared_items.size(); ++i) {
      if (!spec.find(spec.shared_items[i])) {
        shared.at(i).fail("names an unknown item \"" + spec.shared_items[i] + "\"");
      }
    }
  }
  if (root.has("firmware_variants")) {
    const JsonNode variants = root.child("firmware_variants");
    for (std::size_t i = 0, n = variants.array_size(); i < n; ++i) {
      const JsonNode v = variants.at(i);
      v.expect_object(kVariantFields);
      FirmwareVariant variant;
      variant.firmware_version =
          static_cast<std::uint8_t>(v.at("firmware_version").integer(0, kU8));
      if (variant.firmware_version == spec.firmware_version ||
          std::any_of(spec.firmware_variants.begin(), spec.firmware_variants.end(),
                      [&](const FirmwareVariant& other) {
                        return other.firmware_version == variant.firmware_version;
                      })) {
        v.at("firmware_version")
            .fail("lists firmware " + std::to_string(variant.firmware_version) + " twice");
      }
      if (!root.has("indirect")) {
        v.fail("replaces indirect blocks, but the model has no \"indirect\"");
      }
      variant.indirect = read_indirect(v.at("indirect"));
      variant.notes = v.at("notes").strings();
      spec.firmware_variants.push_back(std::move(variant));
    }
    // Built once here so that a variant whose items do not fit is refused with its file.
    for (const FirmwareVariant& variant : spec.firmware_variants) {
      model_for_firmware(spec, variant.firmware_version, origin);
    }
  }
  return spec;
}

std::span<const std::string_view> model_fields() {
  return kModelFields;
}

std::span<const std::string_view> item_fields() {
  return kItemFields;
}

ModelSpec parse_model(std::string_view json_text, const std::string& origin) {
  json document;
  try {
    document = json::parse(json_text);
  } catch (const json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    throw ModelError(origin, "", std::string("not valid JSON: ") + e.what());
  }
  return model_from_json(document, origin);
}

}  // namespace dxlemu::model
