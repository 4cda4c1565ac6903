#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "control/connection.hpp"
#include "control/port_view.hpp"
#include "control/target.hpp"
#include "model/servo.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::control {

/// One item a sampler reads: a servo found once when subscribing (it stays the same servo if its
/// ID changes later: the daemon never destroys a servo), on the port that moves it.
struct SampledItem {
  PortView* port = nullptr;
  model::Servo* servo = nullptr;
  std::size_t item = 0;  ///< the item's index in the servo's control table
};

/// The connections' samplers (sample.subscribe, docs/control-api.md): each sends its connection
/// an event `{"event":"sample","t":...,"values":[...]}` every period of simulated time, on events
/// of Target::schedule_in. At most one per connection. A sampler that is stopped, replaced or
/// outlived by the registry does nothing at its next event and schedules no other: the pending
/// event holds the sampler's state, never the registry.
class Samplers {
 public:
  /// Samplers on `target`, which must outlive them and their pending events.
  explicit Samplers(Target& target);
  /// Stops every sampler.
  ~Samplers();
  Samplers(const Samplers&) = delete;
  Samplers& operator=(const Samplers&) = delete;

  Target& target() { return target_; }

  /// Starts sampling `items` for `connection` every `period` (> 0) of simulated time from now,
  /// replacing the connection's earlier sampler. Keeps a copy of `connection` until stopped.
  void start(const Connection& connection, std::vector<SampledItem> items, sim::SimDuration period);
  /// Stops the sampler of connection `connection` (its id); false when it had none.
  bool stop(std::uint64_t connection);
  /// True while connection `connection` has a sampler.
  bool running(std::uint64_t connection) const { return running_.contains(connection); }

 private:
  struct Sampler;
  // Sends one sample of `sampler` and schedules its next, unless it was stopped meanwhile.
  static void sample(const std::shared_ptr<Sampler>& sampler);
  static void schedule_next(const std::shared_ptr<Sampler>& sampler);

  Target& target_;
  std::map<std::uint64_t, std::shared_ptr<Sampler>> running_;
};

}  // namespace dxlemu::control
