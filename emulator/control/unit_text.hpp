#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

// Reading a model file's unit text ("0.229 [rev/min]") as a factor and a unit, for the control
// API's `table`. Pure functions: no servo, no request.
namespace dxlemu::control {

/// A unit text of the form "NUMBER [UNIT]" read apart: an item's value × `factor` is the quantity
/// in `unit`.
struct ScaledUnit {
  double factor = 1;
  std::string unit;
  bool operator==(const ScaledUnit&) const = default;
};

/// "0.229 [rev/min]" → {0.229, "rev/min"}, "58,000 [rev/min²]" → {58000, "rev/min²"} (commas
/// group thousands), "1[pulse]" → {1, "pulse"}, and FEETECH's bracketless "0.1V" → {0.1, "V"},
/// "8.7°/s²" → {8.7, "°/s²"}. nullopt for anything else, which says more than a factor can
/// ("214.577 [rev/min²] / 1 [ms]", "0.732RPM/0.0146RPM"), names no number ("R", "Step") or is
/// malformed ("16.11328 mA]"): such a unit is shown as written, unscaled.
std::optional<ScaledUnit> scaled_unit(std::string_view text);

/// `value` × `factor` to 12 significant digits: the model files give at most 9, and the
/// product's binary noise (0.229 × 2048 = 468.99199999999996) would otherwise show in the JSON.
double scaled_value(std::int64_t value, double factor);

}  // namespace dxlemu::control
