#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "model/spec/model_error.hpp"
#include "model/spec/model_spec.hpp"

namespace dxlemu::model {

/// Parses and validates a model file's text (format: docs/model-format.md). `origin` names the
/// file in error messages. Throws ModelError naming the JSON pointer and the reason for anything
/// the format does not allow: a missing, mistyped or unknown field, an unknown family, a size
/// other than 1, 2, 4, overlapping items, a duplicate key or address, an initial value outside its
/// range, a bound naming an unknown item, a default baud index not in the table, an indirect
/// block that does not match its items, a byte order other than little or big, a sign bit outside
/// the item or given with "signed": true, an unknown protocol.
ModelSpec parse_model(std::string_view json_text, const std::string& origin);

/// The top-level fields a model file may have (docs/model-format.md). The JSON Schema in
/// models/schema/ declares the same; a test keeps the two in step.
std::span<const std::string_view> model_fields();

/// The fields an item may have.
std::span<const std::string_view> item_fields();

/// As parse_model, from an already parsed document.
ModelSpec model_from_json(const nlohmann::json& document, const std::string& origin);

}  // namespace dxlemu::model
