#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "model/spec/model_spec.hpp"

// A firmware variant as a spec-to-spec transform: the loader reads a model's firmware_variants,
// and this builds the spec of the model running one of them. Kept out of the loader because it
// reads no JSON: it works on a ModelSpec however that was made.

namespace dxlemu::model {

/// `base` running firmware `version`: `base` itself for its own firmware_version, else the
/// variant of firmware_variants with that version, named "NAME@VERSION": its Firmware Version
/// reads `version`, its indirect blocks are the variant's and its Indirect Address/Data items are
/// rebuilt for them from the first pair of `base` (docs/model-format.md). Returns nullopt for a
/// version the model does not list; throws ModelError (naming `origin`) when the rebuilt items
/// overlap the rest of the table.
std::optional<ModelSpec> model_for_firmware(const ModelSpec& base, std::uint8_t version,
                                            const std::string& origin = {});

/// The firmware versions `spec` can run, its default first, as "53, 52".
std::string firmware_list(const ModelSpec& spec);

}  // namespace dxlemu::model
