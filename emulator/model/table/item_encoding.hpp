#pragma once

#include <cstdint>
#include <span>

#include "model/spec/model_spec.hpp"

namespace dxlemu::model {

/// Every value an item can hold, whatever its min and max: the whole width of its size for an
/// unsigned item, two's complement for a `signed` one, and -(2^sign_bit - 1) ~ 2^sign_bit - 1
/// for a sign-magnitude one (docs/model-format.md "Value encodings").
ItemRange representable_range(const ItemSpec& item);

/// The unsigned number held by `bytes`, the first byte the lowest (ByteOrder::Little) or the
/// highest (ByteOrder::Big). At most 8 bytes.
std::uint64_t unpack(ByteOrder order, std::span<const std::uint8_t> bytes);

/// Writes the low `out.size()` bytes of `raw` into `out` in `order`: the inverse of unpack().
void pack(ByteOrder order, std::uint64_t raw, std::span<std::uint8_t> out);

/// The value of `item` held by its `bytes` (exactly item.size of them) in `order`. A
/// sign-magnitude item reads every bit but the sign bit as its magnitude, as FEETECH's SDK does,
/// so bits set above the sign bit make a value outside representable_range(): a bus write of
/// such bytes fails its range check. The sign bit with magnitude 0 ("-0") reads 0.
std::int64_t decode_value(const ItemSpec& item, ByteOrder order,
                          std::span<const std::uint8_t> bytes);

/// The bytes of `item` holding `value` in `order`; `value` must be in representable_range().
/// 0 is written without the sign bit.
void encode_value(const ItemSpec& item, ByteOrder order, std::int64_t value,
                  std::span<std::uint8_t> out);

}  // namespace dxlemu::model
