// dxlemu: a DYNAMIXEL servo-bus emulator. `dxlemu run` serves buses of virtual servos on
// pseudo-terminals; `dxlemu models` lists the model library; `dxlemu robots` the robot profiles;
// `dxlemu check` validates a config or a profile;
// `dxlemu ctl` sends one request to a running emulator's control API; `dxlemu exec` runs a client
// with the preload library that makes the emulator's PTYs behave like a USB adapter.
// `dxlemu clone` scans a real bus and writes the config that serves it.
#include <sys/stat.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>

#include "app/cli/clone_command.hpp"
#include "app/cli/command_line.hpp"
#include "app/cli/ctl_request.hpp"
#include "app/cli/exec_setup.hpp"
#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/config/physics_config.hpp"
#include "app/config/robot_library.hpp"
#include "app/daemon/emulator.hpp"
#include "app/daemon/log.hpp"
#include "io/child_process.hpp"
#include "io/control_client.hpp"
#include "model/spec/model_error.hpp"
#include "wire/protocol.hpp"

namespace {

// Exit status for refused input (bad model file, bad config), as documented in README.md.
constexpr int kExitBadInput = 2;

// "NAME:ID" or "NAME:FIRST-LAST" (model names may contain ':'-free punctuation such as '+'); NAME
// may carry a firmware, "xl330-m288@52", which the library resolves.
std::vector<dxlemu::app::ServoConfig> parse_servo_option(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    throw std::invalid_argument("--servo " + text + ": expected NAME:ID or NAME:FIRST-LAST");
  }
  const std::string name = text.substr(0, colon);
  const std::string ids = text.substr(colon + 1);
  const auto dash = ids.find('-');
  int first = 0;
  int last = 0;
  try {
    std::size_t used = 0;
    first = std::stoi(ids.substr(0, dash), &used);
    if (used != ids.substr(0, dash).size()) {
      throw std::invalid_argument("");
    }
    last = first;
    if (dash != std::string::npos) {
      last = std::stoi(ids.substr(dash + 1), &used);
      if (used != ids.substr(dash + 1).size()) {
        throw std::invalid_argument("");
      }
    }
  } catch (const std::exception&) {
    throw std::invalid_argument("--servo " + text + ": the ID part must be a number or FIRST-LAST");
  }
  if (first < 0 || last > dxlemu::app::kMaxServoId || first > last) {
    throw std::invalid_argument("--servo " + text + ": IDs must lie in 0 ~ 252, first <= last");
  }
  std::vector<dxlemu::app::ServoConfig> out;
  for (int id = first; id <= last; ++id) {
    out.push_back({name, static_cast<std::uint8_t>(id), {}});
  }
  return out;
}

dxlemu::app::ModelLibrary load_library(const std::vector<std::string>& dirs) {
  return dxlemu::app::ModelLibrary::load(
      dxlemu::app::shipped_models_dir(),
      std::vector<std::filesystem::path>(dirs.begin(), dirs.end()));
}

dxlemu::app::RobotLibrary load_robots(const std::vector<std::string>& dirs,
                                      const dxlemu::app::ModelLibrary& models) {
  return dxlemu::app::RobotLibrary::load(
      dxlemu::app::shipped_robots_dir(),
      std::vector<std::filesystem::path>(dirs.begin(), dirs.end()), models);
}

// Runs a subcommand and turns its failures into the documented exit statuses: 2 for refused
// input (bad option, model or config), 1 for anything else (e.g. no pseudo-terminal available).
int run_command(const std::function<void()>& body) {
  try {
    body();
    return 0;
  } catch (const dxlemu::model::ModelError& e) {
    std::cerr << "dxlemu: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "dxlemu: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dxlemu: " << e.what() << "\n";
    return 1;
  }
}

// `dxlemu ctl`'s exit statuses (docs/control-api.md "From a shell: dxlemu ctl"): 0 done, 1 the
// daemon refused the request or failed to answer, 2 bad arguments or no daemon to talk to.
int run_ctl(const dxlemu::app::CtlArguments& ctl) {
  try {
    const auto request = dxlemu::app::ctl_request(ctl.command, ctl.args);
    // Where `dxlemu run` puts its socket by default (the PID part aside).
    const auto dir = dxlemu::app::default_control_path().parent_path();
    const auto path = dxlemu::app::ctl_control_socket(ctl.control, std::getenv("DXLEMU_CONTROL"),
                                                      dir, dxlemu::io::live_control_sockets);
    dxlemu::io::ControlClient client(path);
    const auto timeout = std::chrono::milliseconds(static_cast<std::int64_t>(ctl.timeout_s * 1e3));
    const auto outcome = dxlemu::app::ctl_outcome(client.call(request.dump(), timeout));
    std::cout << outcome.out;
    std::cerr << outcome.err;
    return outcome.exit_code;
  } catch (const std::invalid_argument& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const dxlemu::io::ControlConnectError& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return 1;
  }
}

// `dxlemu exec`'s own failures (docs/exec.md), apart from COMMAND's statuses as env(1) does.
constexpr int kExitExecFailed = 125;
// How long `dxlemu exec` waits for a daemon's port list.
constexpr std::chrono::seconds kExecListTimeout{5};

// The `list` result of the daemon at `socket`; throws naming the socket when it refuses.
nlohmann::json list_ports(const std::filesystem::path& socket) {
  dxlemu::io::ControlClient client(socket);
  const auto reply = nlohmann::json::parse(
      client.call(R"({"id": 1, "cmd": "list"})", kExecListTimeout), nullptr, false);
  if (!reply.is_object() || !reply.value("ok", false)) {
    throw std::runtime_error("the daemon at " + socket.string() + " did not list its ports: " +
                             (reply.is_object() ? reply.value("error", reply.dump()) : "no reply"));
  }
  return reply["result"];
}

bool is_character_device(const std::filesystem::path& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0 && S_ISCHR(status.st_mode);
}

// dxlemu exec: COMMAND with LD_PRELOAD and DXLEMU_PTYS set; its exit status (docs/exec.md).
int run_exec(const dxlemu::app::ExecArguments& arguments) {
  std::map<std::string, std::string> environment;
  try {
    std::error_code error;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
    const auto library = dxlemu::app::preload_library(
        std::getenv("DXLEMU_PRELOAD"), exe.parent_path(), DXLEMU_BINDIR_TO_PRELOADDIR,
        [](const std::filesystem::path& path) {
          std::error_code ignored;
          return std::filesystem::is_regular_file(path, ignored);
        });
    const auto dir = dxlemu::app::default_control_path().parent_path();
    const auto paths = dxlemu::app::exec_pty_paths(arguments, dir, dxlemu::io::live_control_sockets,
                                                   list_ports, is_character_device);
    environment["LD_PRELOAD"] =
        dxlemu::app::append_to_list(std::getenv("LD_PRELOAD"), {library.string()});
    environment["DXLEMU_PTYS"] = dxlemu::app::append_to_list(std::getenv("DXLEMU_PTYS"), paths);
  } catch (const std::exception& e) {
    std::cerr << "dxlemu exec: " << e.what() << "\n";
    return kExitExecFailed;
  }
  try {
    return dxlemu::io::run_child(arguments.command, environment);
  } catch (const std::exception& e) {
    std::cerr << "dxlemu exec: " << e.what() << "\n";
    return kExitExecFailed;
  }
}

std::string protocols_text(const dxlemu::model::ModelSpec& spec) {
  std::string out;
  for (const auto p : spec.protocols) {
    if (!out.empty()) {
      out += ',';
    }
    out += dxlemu::wire::protocol_name(p);
  }
  return out;
}

// Applies --baud and --protocol to every servo of `config`, after its own item overrides.
void apply_bus_options(dxlemu::app::BusConfig& config, const dxlemu::app::ModelLibrary& library,
                       std::optional<std::uint32_t> baud, std::optional<int> protocol) {
  for (auto& port : config.ports) {
    for (auto& servo : port.servos) {
      const auto spec = library.find(servo.model);
      if (!spec) {
        continue;  // check_servo names it
      }
      try {
        if (baud) {
          servo.items.emplace_back("baud_rate", dxlemu::app::baud_rate_item_value(*spec, *baud));
        }
        if (protocol) {
          if (auto item = dxlemu::app::protocol_item(*spec, *protocol)) {
            servo.items.push_back(std::move(*item));
          }
        }
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(baud ? "--baud" : "--protocol") +
                                    (baud && protocol ? "/--protocol" : "") + ": " + e.what());
      }
    }
  }
}

// The one bus of --servo and --link: port dxl0.
dxlemu::app::PortConfig port_of_options(const dxlemu::app::CommandLine& line) {
  dxlemu::app::PortConfig port{"dxl0", std::filesystem::path(line.link), {}, {}, {}};
  std::vector<std::string> servo_options = line.servo_options;
  if (servo_options.empty()) {
    servo_options.emplace_back(dxlemu::app::kDefaultServos);
  }
  for (const std::string& option : servo_options) {
    for (auto& servo : parse_servo_option(option)) {
      port.servos.push_back(std::move(servo));
    }
  }
  return port;
}

// --physics: the physics file it names, attached to `config`.
void attach_physics_option(dxlemu::app::BusConfig& config, const dxlemu::app::CommandLine& line,
                           const dxlemu::app::ModelLibrary& library) {
  if (!line.physics.empty()) {
    const auto robots = load_robots(line.robot_dirs, library);
    dxlemu::app::attach_physics(config, robots.physics_file(line.physics));
  }
}

// dxlemu run: serves until SIGINT, SIGTERM or the control API's shutdown. `link_given`: whether
// --link was on the command line (it has a default).
void serve(const dxlemu::app::CommandLine& line, bool link_given) {
  dxlemu::app::set_log_level(*dxlemu::app::parse_log_level(line.log_level));
  dxlemu::app::RunOptions options = line.options;
  options.timing = dxlemu::app::timing_mode(line.timing);
  options.tick = std::chrono::nanoseconds(std::chrono::seconds(1)) / line.tick_hz;
  options.late_reply_limit = std::chrono::milliseconds(line.late_reply_limit_ms);
  if (line.handover_us) {
    options.pty_handover = std::chrono::microseconds(*line.handover_us);
  }
  const auto library = load_library(line.model_dirs);
  dxlemu::app::BusConfig config;
  if (!line.config_file.empty()) {
    config = dxlemu::app::read_config(line.config_file, library);
  } else if (!line.robot.empty()) {
    const auto robots = load_robots(line.robot_dirs, library);
    config = dxlemu::app::robot_bus(
        robots, line.robot,
        link_given ? std::optional<std::filesystem::path>(line.link) : std::nullopt);
  } else {
    config.ports.push_back(port_of_options(line));
  }
  attach_physics_option(config, line, library);
  apply_bus_options(config, library, line.baud, line.protocol);
  dxlemu::app::Emulator emulator(library, config, options);
  emulator.run(std::cout);
}

// dxlemu check FILE or check --robot NAME: validates a config or a profile and prints its ports.
void check_config(const dxlemu::app::CommandLine& line) {
  const auto library = load_library(line.model_dirs);
  dxlemu::app::BusConfig config;
  std::string checked;
  if (!line.check_robot.empty()) {
    const auto robots = load_robots(line.robot_dirs, library);
    config = dxlemu::app::robot_bus(robots, line.check_robot, std::nullopt);
    checked = line.check_robot + " (" + robots.find(line.check_robot)->file.string() + ")";
  } else if (!line.check_file.empty()) {
    config = dxlemu::app::read_config(line.check_file, library);
    checked = line.check_file;
  } else {
    throw std::invalid_argument("check: give a config FILE or --robot NAME");
  }
  attach_physics_option(config, line, library);
  // The MJCF loads and names every joint (at the default motion tick: `run --tick-hz` may
  // still refuse a timestep that does not divide its own).
  if (config.physics) {
    const auto world = dxlemu::app::load_physics(*config.physics, std::chrono::milliseconds(1));
    for (std::size_t i = 0; i < config.physics->joints.size(); ++i) {
      dxlemu::app::joint_mapping(*config.physics, i, world->world());
    }
  }
  std::cout << checked << ": ok\n";
  for (const auto& port : config.ports) {
    std::cout << "  " << port.name << ": " << port.servos.size()
              << (port.servos.size() == 1 ? " servo" : " servos");
    if (port.link) {
      std::cout << " at " << port.link->string();
    }
    std::cout << "\n";
  }
  if (config.physics) {
    std::cout << "  physics: " << config.physics->mjcf.string() << ", "
              << config.physics->joints.size()
              << (config.physics->joints.size() == 1 ? " joint" : " joints") << "\n";
  }
}

// The servos of every port of `config`.
std::size_t servo_count(const dxlemu::app::BusConfig& config) {
  std::size_t count = 0;
  for (const auto& port : config.ports) {
    count += port.servos.size();
  }
  return count;
}

// dxlemu robots: one line per robot profile, by name.
void list_robots(const dxlemu::app::CommandLine& line) {
  const auto library = load_library(line.model_dirs);
  const auto robots = load_robots(line.robot_dirs, library);
  if (robots.profiles().empty()) {
    std::cerr << "dxlemu: no robot profile in " << dxlemu::app::shipped_robots_dir().string()
              << " or --robots\n";
    return;
  }
  std::size_t name_width = std::string("NAME").size();
  std::size_t title_width = std::string("TITLE").size();
  for (const auto& [name, profile] : robots.profiles()) {
    name_width = std::max(name_width, name.size());
    title_width = std::max(title_width, profile.header().title.size());
  }
  constexpr int kCountWidth = 7;
  // PHYSICS: the shipped physics file of that name, for run --physics (docs/physics.md).
  constexpr int kPhysicsWidth = 9;
  std::cout << std::left << std::setw(static_cast<int>(name_width + 2)) << "NAME"
            << std::setw(kCountWidth) << "PORTS" << std::setw(kCountWidth) << "SERVOS"
            << std::setw(kPhysicsWidth) << "PHYSICS" << std::setw(static_cast<int>(title_width + 2))
            << "TITLE"
            << "SOURCE\n";
  for (const auto& [name, profile] : robots.profiles()) {
    std::cout << std::setw(static_cast<int>(name_width + 2)) << name << std::setw(kCountWidth)
              << profile.config.ports.size() << std::setw(kCountWidth)
              << servo_count(profile.config) << std::setw(kPhysicsWidth)
              << (robots.find_physics(name) != nullptr ? "yes" : "-")
              << std::setw(static_cast<int>(title_width + 2)) << profile.header().title
              << profile.header().sources.front() << "\n";
  }
}

// The filters given to `dxlemu models`, as the user wrote them.
std::string filters_text(const dxlemu::app::ModelsArguments& models) {
  std::string out;
  if (!models.family.empty()) {
    out += " --family " + models.family;
  }
  if (models.protocol) {
    out += " --protocol " + *models.protocol;
  }
  if (!models.name.empty()) {
    out += " --name " + models.name;
  }
  return out;
}

// dxlemu models: one line per model of the library that the filters let through. None is not
// an error (the library was read; it has no such model): stderr says so, the status is 0.
void list_models(const std::vector<std::string>& model_dirs,
                 const dxlemu::app::ModelsArguments& models) {
  const auto filter = dxlemu::app::model_filter(models);
  const auto library = load_library(model_dirs);
  const auto listed = library.select(filter);
  if (listed.empty()) {
    std::cerr << "dxlemu: no model matches" << filters_text(models) << " ("
              << library.names().size() << " in the library)\n";
    return;
  }
  std::cout << std::left << std::setw(18) << "NAME" << std::setw(8) << "NUMBER" << std::setw(10)
            << "PROTOCOLS"
            << "FAMILY\n";
  for (const auto& spec : listed) {
    std::cout << std::setw(18) << spec->name << std::setw(8) << spec->model_number << std::setw(10)
              << protocols_text(*spec) << dxlemu::model::family_name(spec->family) << "\n";
    // Its other firmware, by the name --servo and a config take (NAME@FIRMWARE).
    for (const auto& variant : library.variants_of(spec->name)) {
      std::cout << std::setw(18) << variant->name << std::setw(8) << variant->model_number
                << std::setw(10) << protocols_text(*variant)
                << dxlemu::model::family_name(variant->family) << "\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dxlemu: emulates chains of ROBOTIS DYNAMIXEL servos on pseudo-terminals"};
  dxlemu::app::CommandLine line;
  const dxlemu::app::Subcommands given = dxlemu::app::define_command_line(app, line);
  std::vector<std::string> after_dashes;
  const int parsed_argc = dxlemu::app::exec_split(argc, argv, after_dashes);
  try {
    app.parse(parsed_argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is refused input like a bad config.
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  if (given.run->parsed()) {
    return run_command([&] { serve(line, given.run_link->count() > 0); });
  }
  if (given.ctl->parsed()) {
    return run_ctl(line.ctl);
  }
  if (given.exec->parsed()) {
    try {
      line.exec.command = dxlemu::app::exec_command(*given.exec, after_dashes);
    } catch (const std::invalid_argument& e) {
      std::cerr << "dxlemu exec: " << e.what() << "\n";
      return kExitExecFailed;
    }
    return run_exec(line.exec);
  }
  if (given.clone->parsed()) {
    return run_command([&] {
      dxlemu::app::clone_bus(line.clone, load_library(line.model_dirs), std::cout, std::cerr);
    });
  }
  if (given.check->parsed()) {
    return run_command([&] { check_config(line); });
  }
  if (given.robots->parsed()) {
    return run_command([&] { list_robots(line); });
  }
  if (given.models->parsed()) {
    return run_command([&] { list_models(line.model_dirs, line.models); });
  }
  // No subcommand: say what there is.
  std::cout << app.help();
  return 0;
}
