#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "model/spec/family_traits.hpp"
#include "model/spec/model_spec.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::model {

/// One model of a catalog.json (docs/model-format.md "The catalog"): what the model library knows
/// of a shipped model before it reads the model's file. Enough to find the model by name or
/// number, to list and filter it, and to refuse two models of one name or one number; everything
/// else is in the file. The file must say the same (check_against_catalog).
struct CatalogEntry {
  std::string name;   ///< as the model file's `name`
  std::string title;  ///< as the model file's `title`
  std::uint16_t model_number = 0;
  /// As the model file's `shares_model_number_with`: empty when the file has none.
  std::string shares_model_number_with;
  Family family = Family::X;
  std::vector<wire::Protocol> protocols;  ///< default first, as the file lists them
  /// The model file, relative to the catalog's directory; empty for a model no catalog lists.
  std::string file;
  /// Where the entry is in its catalog ("/models/12"), for messages; empty as `file`.
  std::string pointer;

  /// Who makes the model (its family's maker).
  Maker maker() const { return traits_of(family).maker; }
};

/// The entries of a catalog's text, in catalog order. `origin` names the catalog in errors.
/// Throws ModelError naming the JSON pointer and the reason for invalid JSON, a document without
/// a `models` array, an entry that is not an object, has an unknown member, or lacks or mistypes
/// one: name, title, model_number (0 ~ 65535), family (a known one), protocols (as a model file
/// lists them) and file are required, shares_model_number_with is optional.
std::vector<CatalogEntry> parse_catalog(std::string_view json_text, const std::string& origin);

/// What `spec` says of itself, as a catalog entry without file or pointer: the entry of a model
/// file no catalog lists (a user's, from `dxlemu --models DIR`).
CatalogEntry catalog_entry_of(const ModelSpec& spec);

/// Refuses `spec`, parsed from the file `origin`, unless it says what its catalog entry says:
/// throws ModelError(origin, "/MEMBER", reason) for the first member of name, title,
/// model_number, shares_model_number_with, family, protocols that differs, the reason naming
/// `catalog` (the catalog's file) and the entry's pointer. A catalog is read at start and its
/// files later: a file edited by hand without its entry would otherwise be found under one
/// name or number and serve another.
void check_against_catalog(const ModelSpec& spec, const std::string& origin,
                           const CatalogEntry& entry, const std::string& catalog);

}  // namespace dxlemu::model
