#include "control/sample_commands.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "control/item_commands.hpp"

namespace dxlemu::control {
namespace {

constexpr double kSampleNsPerMs = 1e6;
constexpr std::array<std::string_view, 3> kItemFields = {"port", "servo", "item"};

const Connection& client_of(const Args& args) {
  if (args.connection() == nullptr) {
    refuse(std::string(args.command()) + " needs a connection to send events to");
  }
  return *args.connection();
}

std::string period_range() {
  return "1 ~ 1000 (ms of simulated time)";
}

sim::SimDuration period_of(const Args& args) {
  const auto period = args.number("period_ms");
  if (!period) {
    refuse("\"period_ms\" is required: " + period_range());
  }
  if (!std::isfinite(*period) || *period < kMinSamplePeriodMs || *period > kMaxSamplePeriodMs) {
    refuse("\"period_ms\" must be " + period_range() + ", not " + args.text("period_ms"));
  }
  return sim::SimDuration(static_cast<std::int64_t>(std::llround(*period * kSampleNsPerMs)));
}

/// The items[index] of a request: the servo found now, and the item as the result names it.
struct Resolved {
  SampledItem item;
  ordered_json named;
};

Resolved resolve(Target& target, const ordered_json& entry, std::size_t index,
                 std::string_view command) {
  const std::string where = "items[" + std::to_string(index) + "]";
  if (!entry.is_object()) {
    refuse(where + " must be an object {\"port\"?, \"servo\", \"item\"}");
  }
  for (const auto& [key, value] : entry.items()) {
    if (std::find(kItemFields.begin(), kItemFields.end(), key) == kItemFields.end()) {
      refuse("unknown field " + json_quoted(key) + " in " + where +
             " (an item takes port, servo, item)");
    }
  }
  const Args args(entry, command);
  const auto key = args.string("item");
  if (!key) {
    refuse(where + ": \"item\" is required (an item's key, e.g. \"present_position\")");
  }
  // The same lookups, and refusals, as get.
  const Port port = port_of(target, args);
  model::Servo& servo = servo_on(port, args.required_integer("servo"));
  const std::size_t item = item_named(servo.spec(), *key);
  return {{&port.view, &servo, item},
          {{"port", port.name}, {"servo", servo.id()}, {"item", servo.spec().items[item].key}}};
}

}  // namespace

ordered_json sample_subscribe(Samplers& samplers, const Args& args) {
  const Connection& client = client_of(args);
  const ordered_json* entries = args.value("items");
  if (entries == nullptr || !entries->is_array()) {
    refuse("\"items\" is required: a list of up to " + std::to_string(kMaxSampledItems) +
           " items {\"port\"?, \"servo\", \"item\"}");
  }
  if (entries->empty() || entries->size() > kMaxSampledItems) {
    refuse("\"items\" must hold 1 ~ " + std::to_string(kMaxSampledItems) + " items, not " +
           std::to_string(entries->size()));
  }
  const sim::SimDuration period = period_of(args);
  std::vector<SampledItem> items;
  ordered_json named = ordered_json::array();
  for (std::size_t i = 0; i < entries->size(); ++i) {
    Resolved resolved = resolve(samplers.target(), (*entries)[i], i, args.command());
    items.push_back(resolved.item);
    named.push_back(std::move(resolved.named));
  }
  // Only a request that is accepted whole replaces the sampler running.
  samplers.start(client, std::move(items), period);
  return {{"items", std::move(named)}, {"period_ms", *args.value("period_ms")}};
}

ordered_json sample_unsubscribe(Samplers& samplers, const Args& args) {
  return {{"stopped", samplers.stop(client_of(args).id)}};
}

}  // namespace dxlemu::control
