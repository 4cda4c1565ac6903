#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/config/robot_request.hpp"

namespace dxlemu::app {

/// One robot profile: a bus config with a robot header (docs/robots.md), read from `file`.
struct RobotProfile {
  std::filesystem::path file;  ///< where it was read, for messages and `dxlemu robots`
  BusConfig config;            ///< its ports and servos; config.robot is always set
  /// The header (config.robot), for brevity.
  const RobotHeader& header() const { return *config.robot; }
};

/// Every robot profile `--robot` can name: the shipped ones (robots/*.json) and those of any
/// directories given with --robots, which may add profiles or replace a shipped one of the same
/// name. Loading is all or nothing: a bad profile throws ConfigError naming its file, the JSON
/// pointer and the reason.
class RobotLibrary {
 public:
  /// Reads every *.json file of `shipped_dir` (none when it does not exist), then of each
  /// `extra_dirs` directory (which must exist), checking each against `models` as a config is
  /// checked; and notes the physics/*.json files of each (read when attached). Each file must have
  /// a robot header whose name is the file's name without ".json"; its ports' `robot` is that
  /// name. Once all are read, each profile's `pairs_with` must name a profile of the opposite
  /// role that names it back (ConfigError at /robot/pairs_with of the profile naming it).
  static RobotLibrary load(const std::filesystem::path& shipped_dir,
                           const std::vector<std::filesystem::path>& extra_dirs,
                           const ModelLibrary& models);

  /// The profile named `name`, or nullptr.
  const RobotProfile* find(const std::string& name) const;
  /// Why find(`name`) found nothing, naming the known profiles, for an error message.
  std::string why_not_found(const std::string& name) const;
  /// All profiles, by name.
  const std::map<std::string, RobotProfile>& profiles() const { return profiles_; }
  /// Every leader and follower pair (docs/robots.md "Leaders and followers"), once each as
  /// (leader, follower), in the leaders' name order.
  std::vector<std::pair<std::string, std::string>> pairs() const;
  /// The physics file called `name` (physics/NAME.json beside the profiles), or nullptr.
  const std::filesystem::path* find_physics(const std::string& name) const;
  /// The file `dxlemu run --physics ARGUMENT` attaches: ARGUMENT when it is a file, else the
  /// physics file it names. Throws std::invalid_argument naming the known ones.
  std::filesystem::path physics_file(const std::string& argument) const;

 private:
  void add_directory(const std::filesystem::path& dir, const ModelLibrary& models);
  void check_pairs() const;

  std::map<std::string, RobotProfile> profiles_;
  std::map<std::string, std::filesystem::path> physics_;
};

/// Attaches the physics file `file` to `config` (`--physics`). Throws std::invalid_argument when
/// the config has physics already, ConfigError naming the file, pointer and reason for a bad
/// file (or a build without MuJoCo).
void attach_physics(BusConfig& config, const std::filesystem::path& file);

/// The bus `dxlemu run --robot NAME` serves: the profile `name`'s config, with `link` (run's
/// --link, when given) as its port's link. Throws std::invalid_argument naming the known
/// profiles for an unknown name, and for a link given to a profile of several ports (each port
/// has its own link in the profile; a copy of the profile changes them).
BusConfig robot_bus(const RobotLibrary& robots, const std::string& name,
                    const std::optional<std::filesystem::path>& link);

/// The name port `port` of robot `robot` has in a daemon serving several robots (`dxlemu run
/// --robot A --robot B`): the robot's name for a profile of one port (`robot_ports` 1), else
/// ROBOT.PORT, so that every port's name is unique and says whose it is.
std::string served_port_name(const std::string& robot, const std::string& port,
                             std::size_t robot_ports);

/// The bus `dxlemu run --robot NAME...` serves: each requested profile's ports, in the order of
/// `requests`, with the physics file each request names attached to that robot's ports (parsed
/// against them; `link` is run's --link). One robot: robot_bus() with its physics, port names as
/// in the profile. Several: each port renamed by served_port_name() (the physics joints' ports
/// too), no robot header. Throws std::invalid_argument (naming the option and what clashes) for
/// an unknown profile, a robot asked for twice, a link given for several robots, physics on more
/// than one robot (a daemon has one world), two ports on one link or with one name; ConfigError
/// for a bad physics file.
BusConfig robots_bus(const RobotLibrary& robots, const std::vector<RobotRequest>& requests,
                     const std::optional<std::filesystem::path>& link);

/// The directory of the shipped robot profiles, found as shipped_models_dir() finds the models:
/// $DXLEMU_ROBOTS_DIR when set and not empty; the installed profiles beside the running
/// executable (`../share/dxlemu/robots` by default) when that directory exists; else the
/// source tree's robots/ this binary was built from.
std::filesystem::path shipped_robots_dir();

}  // namespace dxlemu::app
