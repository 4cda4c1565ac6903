#include "control/samplers.hpp"

#include <algorithm>
#include <utility>

#include "control/request.hpp"

namespace dxlemu::control {

struct Samplers::Sampler {
  Target& target;
  Connection connection;
  std::vector<SampledItem> items;
  sim::SimDuration period;
  sim::SimTime next;     // when the next sample is due
  bool stopped = false;  // set by stop(), a replacement or the registry's end
};

Samplers::Samplers(Target& target) : target_(target) {}

Samplers::~Samplers() {
  for (auto& [id, sampler] : running_) {
    sampler->stopped = true;
  }
}

void Samplers::start(const Connection& connection, std::vector<SampledItem> items,
                     sim::SimDuration period) {
  stop(connection.id);
  auto sampler = std::make_shared<Sampler>(
      Sampler{target_, connection, std::move(items), period, target_.now() + period});
  running_[connection.id] = sampler;
  schedule_next(sampler);
}

bool Samplers::stop(std::uint64_t connection) {
  const auto found = running_.find(connection);
  if (found == running_.end()) {
    return false;
  }
  found->second->stopped = true;
  running_.erase(found);
  return true;
}

void Samplers::schedule_next(const std::shared_ptr<Sampler>& sampler) {
  // Due times count from the start, not from each event: no drift, whatever the period's
  // rounding to nanoseconds.
  sampler->target.schedule_in(sampler->next - sampler->target.now(),
                              [sampler] { sample(sampler); });
}

void Samplers::sample(const std::shared_ptr<Sampler>& sampler) {
  if (sampler->stopped) {
    return;
  }
  // Each port's motion caught up once: every item of a port is read at the same instant.
  std::vector<PortView*> caught_up;
  for (const SampledItem& item : sampler->items) {
    if (std::find(caught_up.begin(), caught_up.end(), item.port) == caught_up.end()) {
      item.port->catch_up();
      caught_up.push_back(item.port);
    }
  }
  ordered_json values = ordered_json::array();
  for (const SampledItem& item : sampler->items) {
    if (item.port->attached(*item.servo)) {
      values.push_back(item.servo->table().get(item.item));
    } else {
      values.push_back(nullptr);  // unplugged: nothing to read
    }
  }
  constexpr double kNsPerS = 1e9;
  const ordered_json event = {
      {"event", "sample"},
      {"t", static_cast<double>(sim::ns_since_start(sampler->target.now())) / kNsPerS},
      {"values", std::move(values)}};
  sampler->connection.send(dumped(event));
  // Sending may have closed the connection (and stopped the sampler).
  if (!sampler->stopped) {
    sampler->next += sampler->period;
    schedule_next(sampler);
  }
}

}  // namespace dxlemu::control
