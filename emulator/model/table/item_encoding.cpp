#include "model/table/item_encoding.hpp"

namespace dxlemu::model {

ItemRange representable_range(const ItemSpec& item) {
  const int bits = 8 * item.size;
  if (item.sign_bit) {
    const std::int64_t magnitude = (std::int64_t{1} << *item.sign_bit) - 1;
    return {-magnitude, magnitude};
  }
  if (item.is_signed) {
    return {-(std::int64_t{1} << (bits - 1)), (std::int64_t{1} << (bits - 1)) - 1};
  }
  return {0, (std::int64_t{1} << bits) - 1};
}

std::uint64_t unpack(ByteOrder order, std::span<const std::uint8_t> bytes) {
  std::uint64_t raw = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const std::size_t from = order == ByteOrder::Little ? bytes.size() - 1 - i : i;
    raw = (raw << 8) | bytes[from];
  }
  return raw;
}

void pack(ByteOrder order, std::uint64_t raw, std::span<std::uint8_t> out) {
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::size_t to = order == ByteOrder::Little ? i : out.size() - 1 - i;
    out[to] = static_cast<std::uint8_t>(raw >> (8 * i));
  }
}

std::int64_t decode_value(const ItemSpec& item, ByteOrder order,
                          std::span<const std::uint8_t> bytes) {
  const std::uint64_t raw = unpack(order, bytes.first(item.size));
  if (item.sign_bit) {
    const std::uint64_t sign = std::uint64_t{1} << *item.sign_bit;
    const auto magnitude = static_cast<std::int64_t>(raw & ~sign);
    return (raw & sign) != 0 ? -magnitude : magnitude;
  }
  if (item.is_signed) {
    const std::uint64_t sign = std::uint64_t{1} << (8 * item.size - 1);
    return static_cast<std::int64_t>(raw ^ sign) - static_cast<std::int64_t>(sign);
  }
  return static_cast<std::int64_t>(raw);
}

void encode_value(const ItemSpec& item, ByteOrder order, std::int64_t value,
                  std::span<std::uint8_t> out) {
  std::uint64_t raw = 0;
  if (item.sign_bit && value < 0) {
    raw = static_cast<std::uint64_t>(-value) | (std::uint64_t{1} << *item.sign_bit);
  } else {
    raw = static_cast<std::uint64_t>(value);  // two's complement for a negative signed value
  }
  pack(order, raw, out.first(item.size));
}

}  // namespace dxlemu::model
