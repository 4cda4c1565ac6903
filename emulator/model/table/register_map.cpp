// The control table seen through a protocol that addresses registers of two bytes (Modbus RTU,
// docs/modbus.md "The register map"): register 40001 + floor(A / 2) holds bytes A (low) and
// A + 1 (high) of an even address A, and the items a page prints "N/A" for are out of reach.
#include <string>

#include "model/table/control_table.hpp"

namespace dxlemu::model {

bool ControlTable::absent(std::size_t address, wire::Protocol protocol) const {
  if (address >= image_.size()) {
    return false;
  }
  const int item = item_at_[address];
  return item >= 0 && !spec_->items[static_cast<std::size_t>(item)].present_in(protocol);
}

bool ControlTable::takes_write(std::size_t address, wire::Protocol protocol) const {
  if (address >= image_.size()) {
    return false;
  }
  const int item = item_at_[address];
  if (item < 0) {
    return false;
  }
  const ItemSpec& spec = spec_->items[static_cast<std::size_t>(item)];
  return spec.present_in(protocol) && spec.access == Access::ReadWrite;
}

std::optional<TableResult> ControlTable::skip_in_register(std::size_t address, std::size_t first,
                                                          std::size_t length,
                                                          wire::Protocol protocol) const {
  if (takes_write(address, protocol)) {
    return std::nullopt;
  }
  // The other bytes of its register, as far as the write covers them: one that takes the
  // write carries the register, and this byte's value does not matter (the ID in the high byte
  // of 40004 beside the read-only Firmware Version).
  const std::size_t word = wire::traits(protocol).register_bytes;
  const std::size_t start = address - address % word;
  for (std::size_t b = start; b < start + word; ++b) {
    if (b != address && b >= first && b < first + length && takes_write(b, protocol)) {
      return TableResult{};
    }
  }
  return TableResult::fail(TableError::Access,
                           "register " + std::to_string(start / word) + " (bytes " +
                               std::to_string(start) + " ~ " + std::to_string(start + word - 1) +
                               ") holds nothing " + std::string(wire::protocol_title(protocol)) +
                               " can write on " + spec_->name);
}

TableResult ControlTable::bus_read(std::uint16_t address, std::uint16_t length,
                                   std::vector<std::uint8_t>& out, wire::Protocol protocol) const {
  TableResult result = bus_read(address, length, out);
  const std::size_t word = wire::traits(protocol).register_bytes;
  if (!result.ok() || word <= 1) {
    return result;
  }
  for (std::size_t start = address - address % word; start < std::size_t{address} + length;
       start += word) {
    bool all_absent = true;
    for (std::size_t b = start; b < start + word; ++b) {
      all_absent = all_absent && absent(b, protocol);
    }
    if (all_absent) {
      out.clear();  // a refused read yields no data
      return TableResult::fail(TableError::Access, "register " + std::to_string(start / word) +
                                                       " holds only items " +
                                                       std::string(wire::protocol_title(protocol)) +
                                                       " leaves out on " + spec_->name);
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (absent(address + i, protocol)) {
      out[i] = 0;
    }
  }
  return result;
}

TableResult ControlTable::check_id(std::size_t item, std::int64_t value,
                                   wire::Protocol protocol) const {
  if (!id_ || item != *id_) {
    return {};
  }
  // The ID is the device's address in the protocol it is written in: over Modbus RTU 1 ~ 247
  // (the P pages: "1 ~ 247 (Modbus)"), where the item's own range is 2.0's.
  const wire::ProtocolTraits& row = wire::traits(protocol);
  if (value < row.min_unicast_id || value > row.max_unicast_id) {
    return TableResult::fail(TableError::DataRange, std::to_string(value) + " is not an ID of " +
                                                        std::string(row.title) + " (" +
                                                        std::to_string(row.min_unicast_id) + " ~ " +
                                                        std::to_string(row.max_unicast_id) + ")");
  }
  return {};
}

}  // namespace dxlemu::model
