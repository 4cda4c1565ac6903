#include "control/item_commands.hpp"

#include <cstdint>
#include <vector>

#include "model/servo.hpp"

namespace dxlemu::control {

std::size_t item_named(const model::ModelSpec& spec, const std::string& key) {
  const auto index = spec.index_of(key);
  if (!index) {
    refuse(spec.name + " has no item " + json_quoted(key));
  }
  return *index;
}

namespace {

// The widest value get and set handle by address (the widest control-table item).
constexpr std::int64_t kMaxValueBytes = 4;

struct ByteRange {
  std::int64_t address = 0;
  std::int64_t size = 0;
};

std::string range_text(const ByteRange& range) {
  return "address " + std::to_string(range.address) + " size " + std::to_string(range.size);
}

/// The "address" and "size" of a request, within `spec`'s control table.
ByteRange byte_range(const Args& args, const model::ModelSpec& spec) {
  if (!args.has("address") && !args.has("size")) {
    refuse(std::string(args.command()) + " needs \"item\", or \"address\" and \"size\"");
  }
  const ByteRange range{args.required_integer("address"), args.required_integer("size")};
  if (range.size < 1 || range.size > kMaxValueBytes) {
    refuse("\"size\" must be 1 ~ " + std::to_string(kMaxValueBytes));
  }
  const auto table_size = static_cast<std::int64_t>(spec.table_size());
  if (range.address < 0 || range.address + range.size > table_size) {
    refuse(range_text(range) + " is outside the control table of " + spec.name + " (0 ~ " +
           std::to_string(table_size - 1) + ")");
  }
  return range;
}

/// The item a request names: by "item", or by an address range that is exactly one item.
std::size_t item_of(const Args& args, const model::ModelSpec& spec) {
  if (const auto key = args.string("item")) {
    if (args.has("address") || args.has("size")) {
      refuse("give \"item\" or \"address\" and \"size\", not both");
    }
    return item_named(spec, *key);
  }
  const ByteRange range = byte_range(args, spec);
  for (std::size_t i = 0; i < spec.items.size(); ++i) {
    const model::ItemSpec& item = spec.items[i];
    if (item.address == range.address) {
      if (item.size == range.size) {
        return i;
      }
      refuse(range_text(range) + " is not exactly one item of " + spec.name + ": " + item.key +
             " at " + std::to_string(item.address) + " is " + byte_count(item.size));
    }
  }
  refuse(range_text(range) + " is not exactly one item of " + spec.name);
}

}  // namespace

ordered_json get(Target& target, const Args& args) {
  const model::Servo& servo = addressed(target, args);
  const model::ModelSpec& spec = servo.spec();
  if (args.has("item")) {
    const std::size_t index = item_of(args, spec);
    return {{"item", spec.items[index].key}, {"value", servo.table().get(index)}};
  }
  const ByteRange range = byte_range(args, spec);
  const auto address = static_cast<std::size_t>(range.address);
  const auto size = static_cast<std::size_t>(range.size);
  const auto bytes = servo.table().bytes().subspan(address, size);
  return {{"address", range.address},
          {"size", range.size},
          {"value", servo.table().raw_value(address, size)},
          {"bytes", std::vector<std::uint8_t>(bytes.begin(), bytes.end())}};
}

ordered_json set(Target& target, const Args& args) {
  model::Servo& servo = addressed(target, args);
  const std::size_t index = item_of(args, servo.spec());
  const model::ItemSpec& item = servo.spec().items[index];
  const std::int64_t value = args.required_integer("value");
  if (!model::ControlTable::fits(item, value)) {
    refuse("value " + std::to_string(value) + " does not fit " + item.key + " (" +
           byte_count(item.size) + ")");
  }
  servo.device_write(index, value);
  return {{"item", item.key}, {"value", servo.table().get(index)}};
}

}  // namespace dxlemu::control
