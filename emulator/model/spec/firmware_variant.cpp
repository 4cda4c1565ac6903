#include "model/spec/firmware_variant.hpp"

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

#include "model/spec/model_error.hpp"

namespace dxlemu::model {
namespace {

// One past the last Indirect Data address of `blocks`.
std::int64_t data_end(const std::vector<IndirectBlock>& blocks) {
  std::int64_t end = 0;
  for (const IndirectBlock& b : blocks) {
    end = std::max<std::int64_t>(end, b.data + b.count);
  }
  return end;
}

}  // namespace

std::optional<ModelSpec> model_for_firmware(const ModelSpec& base, std::uint8_t version,
                                            const std::string& origin) {
  if (version == base.firmware_version) {
    return base;
  }
  const auto variant =
      std::find_if(base.firmware_variants.begin(), base.firmware_variants.end(),
                   [&](const FirmwareVariant& v) { return v.firmware_version == version; });
  if (variant == base.firmware_variants.end()) {
    return std::nullopt;
  }
  const std::string at = "/firmware_variants/" +
                         std::to_string(variant - base.firmware_variants.begin()) + "/indirect";
  if (base.indirect.empty()) {
    throw ModelError(origin, at, "replaces indirect blocks, but the model has none");
  }
  // The first pair of the model's own blocks is the pattern of every rebuilt pair: same access,
  // area and range; an address item's initial points at its Data item as the model's does.
  const ItemSpec* address_item = nullptr;
  const ItemSpec* data_item = nullptr;
  std::set<std::uint16_t> dropped;
  for (const IndirectBlock& b : base.indirect) {
    for (std::uint16_t i = 0; i < b.count; ++i) {
      dropped.insert(static_cast<std::uint16_t>(b.address + 2 * i));
      dropped.insert(static_cast<std::uint16_t>(b.data + i));
    }
  }
  for (const ItemSpec& item : base.items) {
    if (item.address == base.indirect.front().address) {
      address_item = &item;
    } else if (item.address == base.indirect.front().data) {
      data_item = &item;
    }
  }
  // check_indirect() makes sure both exist when a file is loaded; a spec built otherwise may lack
  // them.
  if (address_item == nullptr || data_item == nullptr) {
    throw ModelError(origin, at, "the model's first indirect block has no items to copy");
  }
  const std::int64_t points_past = address_item->initial - base.indirect.front().data;
  const std::int64_t old_end = data_end(base.indirect);
  const std::int64_t new_end = data_end(variant->indirect);

  // Bounds and initial_from are indices into `items`; rebuilding moves them, so they are kept by
  // key and resolved again in the new order.
  auto key_of = [&](std::size_t index) { return base.items[index].key; };
  struct Kept {
    ItemSpec spec;
    std::optional<std::string> initial_from, limit_min, limit_max;
  };
  std::vector<Kept> kept;
  for (const ItemSpec& item : base.items) {
    if (dropped.count(item.address) != 0) {
      continue;
    }
    Kept k{item, {}, {}, {}};
    if (item.initial_from) {
      k.initial_from = key_of(*item.initial_from);
    }
    if (item.limit_min) {
      k.limit_min = key_of(item.limit_min->item);
    }
    if (item.limit_max) {
      k.limit_max = key_of(item.limit_max->item);
    }
    if (k.spec.key == "firmware_version") {
      k.spec.initial = version;
    }
    kept.push_back(std::move(k));
  }
  std::size_t n = 1;
  for (const IndirectBlock& b : variant->indirect) {
    for (std::uint16_t i = 0; i < b.count; ++i, ++n) {
      ItemSpec a = *address_item;
      a.key = "indirect_address_" + std::to_string(n);
      a.name = "Indirect Address " + std::to_string(n);
      a.address = static_cast<std::uint16_t>(b.address + 2 * i);
      a.initial = b.data + i + points_past;
      // The range of an Indirect Address ends at the table's last Data byte, which moves with it.
      if (a.max == old_end - 1) {
        a.max = new_end - 1;
      }
      ItemSpec d = *data_item;
      d.key = "indirect_data_" + std::to_string(n);
      d.name = "Indirect Data " + std::to_string(n);
      d.address = static_cast<std::uint16_t>(b.data + i);
      kept.push_back({std::move(a), {}, {}, {}});
      kept.push_back({std::move(d), {}, {}, {}});
    }
  }
  std::stable_sort(kept.begin(), kept.end(),
                   [](const Kept& x, const Kept& y) { return x.spec.address < y.spec.address; });
  for (std::size_t i = 0; i + 1 < kept.size(); ++i) {
    if (kept[i].spec.end() > kept[i + 1].spec.address) {
      throw ModelError(origin, at,
                       "item \"" + kept[i + 1].spec.key + "\" at " +
                           std::to_string(kept[i + 1].spec.address) + " overlaps \"" +
                           kept[i].spec.key + "\" for firmware " + std::to_string(version));
    }
  }
  ModelSpec spec = base;
  spec.name = base.name + "@" + std::to_string(version);
  spec.firmware_version = version;
  spec.indirect = variant->indirect;
  spec.firmware_variants.clear();
  spec.notes.insert(spec.notes.end(), variant->notes.begin(), variant->notes.end());
  spec.items.clear();
  for (const Kept& k : kept) {
    spec.items.push_back(k.spec);
  }
  spec.index_items();
  // An item bounded by (or starting from) an Indirect item the variant dropped has nothing left to
  // follow: refused rather than left pointing at another item.
  auto index_of = [&](const std::string& item_key, const std::string& of) {
    const auto index = spec.index_of(item_key);
    if (!index) {
      throw ModelError(origin, at,
                       "\"" + of + "\" names \"" + item_key + "\", which firmware " +
                           std::to_string(version) + " does not have");
    }
    return *index;
  };
  for (std::size_t i = 0; i < kept.size(); ++i) {
    ItemSpec& item = spec.items[i];
    if (kept[i].initial_from) {
      item.initial_from = index_of(*kept[i].initial_from, item.key);
    }
    if (kept[i].limit_min) {
      item.limit_min->item = index_of(*kept[i].limit_min, item.key);
    }
    if (kept[i].limit_max) {
      item.limit_max->item = index_of(*kept[i].limit_max, item.key);
    }
    if (!item.in_range(item.initial)) {
      throw ModelError(origin, at,
                       "\"" + item.key + "\" would start at " + std::to_string(item.initial) +
                           ", outside its range, for firmware " + std::to_string(version));
    }
  }
  return spec;
}

std::string firmware_list(const ModelSpec& spec) {
  std::string out = std::to_string(spec.firmware_version);
  for (const FirmwareVariant& v : spec.firmware_variants) {
    out += ", " + std::to_string(v.firmware_version);
  }
  return out;
}

}  // namespace dxlemu::model
