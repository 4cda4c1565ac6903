#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "model/motion/joint_coupling.hpp"
#include "physics/world_clock.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::app {

struct PortConfig;

/// One servo driving one joint ("physics"/"joints" entries, docs/physics.md).
struct JointConfig {
  std::string port;
  std::uint8_t id = 1;
  std::string joint;
  /// Shaft turns per joint turn.
  double gear = 1;
  /// 1 or -1: whether the shaft's positive direction turns the joint positively.
  int direction = 1;
  /// The shaft's angle when the joint is at 0, degrees.
  double zero_offset_deg = 0;
  bool operator==(const JointConfig&) const = default;
};

/// A config's "physics" object: the MJCF world and which servo drives which joint.
struct PhysicsConfig {
  /// The MJCF file, relative to the config file's folder when read_config() read it.
  std::filesystem::path mjcf;
  /// The world's timestep; nullopt: one motion tick.
  std::optional<double> timestep_ms;
  std::vector<JointConfig> joints;
  /// The config file (or request) it came from, for errors found when the world is loaded.
  std::string origin;
  /// Where in `origin` the object is: "/physics" in a config, "" in a physics file.
  std::string pointer = "/physics";
  bool operator==(const PhysicsConfig&) const = default;
};

/// Parses the physics object `value`, at JSON pointer `pointer` of file `origin`, against the
/// config's `ports` (already parsed). Throws ConfigError naming the JSON pointer and the reason;
/// also when this build has no MuJoCo.
PhysicsConfig parse_physics(const nlohmann::json& value, const std::string& origin,
                            const std::vector<PortConfig>& ports,
                            const std::string& pointer = "/physics");

/// Reads a physics file (`dxlemu run --physics FILE`): one physics object, as a config's
/// "physics" member, whose "mjcf" is relative to the file's folder. Throws ConfigError naming
/// the file, the JSON pointer and the reason.
PhysicsConfig read_physics_file(const std::filesystem::path& file,
                                const std::vector<PortConfig>& ports);

/// Loads the world of `config` stepping in motion ticks of `tick`. Throws ConfigError (naming
/// /physics/mjcf or /physics/timestep_ms) when the MJCF does not load or the timestep does not
/// divide the tick.
std::unique_ptr<physics::WorldClock> load_physics(const PhysicsConfig& config,
                                                  sim::SimDuration tick);

/// The mapping of `config.joints[index]` onto `world`. Throws ConfigError naming
/// /physics/joints/INDEX/joint when the world has no such joint.
model::JointMapping joint_mapping(const PhysicsConfig& config, std::size_t index,
                                  const physics::World& world);

}  // namespace dxlemu::app
