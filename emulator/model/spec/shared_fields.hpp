#pragma once

#include <vector>

#include "model/spec/family_traits.hpp"
#include "model/spec/json_node.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::model {

// The members a model file and its catalog entry both state (docs/model-format.md "The
// catalog"), read the same way in both so that a catalog entry and its file can only disagree
// in value, never in spelling.

/// The `family` member: a family name of the traits table; refused naming the known ones.
Family read_family(const JsonNode& family);

/// The `protocols` member: each 1, 2 or "feetech", none twice, at least one, every one of
/// `family`'s maker. The one place that maps their JSON spelling to wire::Protocol, so that a
/// new protocol is one more case here (and in the schema).
std::vector<wire::Protocol> read_protocols(const JsonNode& protocols, Family family);

/// An item's `absent_in` member: protocols spelled as in `protocols` (numbers or strings), at
/// least one, none twice, each one the model lists in `model_protocols`, and not all of them (an
/// item no protocol reaches is no item). Refused with the member's JSON pointer and the reason.
std::vector<wire::Protocol> read_absent_in(const JsonNode& absent_in,
                                           const std::vector<wire::Protocol>& model_protocols);

}  // namespace dxlemu::model
