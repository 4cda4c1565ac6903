#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "model/servo.hpp"
#include "physics/world_clock.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::test {

/// The shipped model library (models/ and its maker folders), loaded once.
const app::ModelLibrary& shipped_library();

/// The robot profile `profile` (robots/NAME.json) with the physics file `physics`
/// (robots/physics/NAME.json) attached, as `dxlemu run --config PROFILE --physics PHYSICS`
/// serves it.
app::BusConfig profile_with_physics(const std::filesystem::path& profile,
                                    const std::filesystem::path& physics);

/// The servos of a config on one virtual clock: with physics, every servo the config's physics
/// couples is on its joint of one MuJoCo world; without, the same servos stand alone. Servos
/// are in the order of the config's ports and servos; each gets its item overrides as the
/// daemon applies them.
class ArmRig {
 public:
  /// `with_physics` false builds the same servos without the world (for comparisons).
  explicit ArmRig(const app::BusConfig& config, bool with_physics = true,
                  sim::SimDuration tick = std::chrono::milliseconds(1));

  /// The first servo of ID `id` (on any port).
  model::Servo& servo(std::uint8_t id);
  std::vector<std::unique_ptr<model::Servo>>& servos() { return servos_; }
  /// The world's clock; nullptr without physics.
  physics::WorldClock* clock() { return clock_.get(); }

  /// Simulated time now.
  sim::SimTime now() const { return now_; }
  /// Moves simulated time on by `d`, catching every servo (and so the world) up.
  void wait(sim::SimDuration d);
  /// Item `key` of servo `id` as the control table holds it.
  std::int64_t get(std::uint8_t id, const std::string& key);
  /// Writes item `key` of servo `id` device-side, at now().
  void set(std::uint8_t id, const std::string& key, std::int64_t value);
  /// Every servo's control table bytes, concatenated in servo order.
  std::vector<std::uint8_t> table_bytes() const;

 private:
  std::unique_ptr<physics::WorldClock> clock_;  // outlives the servos coupled to it
  std::vector<std::unique_ptr<model::Servo>> servos_;
  sim::SimTime now_{};
};

/// What holding still takes in a separate MuJoCo run of `mjcf`: each joint's generalized bias
/// force (gravity, at rest) with the joints named in `qpos` at those positions (rad or m) and
/// every other at its qpos0, by joint name. N·m on a hinge, N on a slide.
std::map<std::string, double> holding_forces(const std::filesystem::path& mjcf,
                                             const std::map<std::string, double>& qpos);

}  // namespace dxlemu::test
