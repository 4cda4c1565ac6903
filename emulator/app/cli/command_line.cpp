#include "app/cli/command_line.hpp"

#include <chrono>
#include <map>
#include <stdexcept>
#include <utility>

#include "dxlemu/version.hpp"

namespace dxlemu::app {
namespace {

// How long `dxlemu ctl` waits for a reply by default: long enough for a clock.step of an hour.
constexpr double kDefaultCtlTimeoutS = 60;

constexpr const char* kDefaultLink = "/tmp/dxlemu-dxl0";

// --tick-hz: 1 kHz by default (docs/motion.md); 10 Hz ~ 10 kHz accepted.
constexpr int kDefaultTickHz = 1000;
constexpr int kMinTickHz = 10;
constexpr int kMaxTickHz = 10000;

const std::map<std::string, TimingMode> kTimingModes = {
    {"realtime", TimingMode::Realtime}, {"fast", TimingMode::Fast}, {"manual", TimingMode::Manual}};

std::string unknown_family(const std::string& name) {
  return "unknown family \"" + name + "\" (known: " + model::family_names() + ")";
}

// --models, which every subcommand that loads the model library takes.
void add_models_option(CLI::App& cmd, CommandLine& line) {
  cmd.add_option("--models", line.model_dirs,
                 "Also load every *.json model file of DIR (repeatable); a file replaces the "
                 "shipped model of the same name")
      ->check(CLI::ExistingDirectory);
}

CLI::App* add_models(CLI::App& app, CommandLine& line) {
  auto* models =
      app.add_subcommand("models", "List the model library: name, model number, protocols");
  add_models_option(*models, line);
  ModelsArguments& filters = line.models;
  models
      ->add_option("--family", filters.family,
                   "Only the models of this behaviour family: " + model::family_names())
      ->check(CLI::Validator(
          [](const std::string& name) {
            return model::family_from_name(name) ? std::string() : unknown_family(name);
          },
          "FAMILY"));
  models
      ->add_option("--protocol", filters.protocol,
                   "Only the models that can speak this protocol: 1, 2 (DYNAMIXEL), modbus "
                   "(Modbus RTU) or feetech")
      ->check(CLI::IsMember(wire::protocol_spellings()));
  models->add_option("--name", filters.name,
                     "Only the models whose name or title contains TEXT, ignoring case");
  models->footer(
      "Filters combine: a model is listed when it meets all of them. When none does, nothing "
      "is listed, stderr says so and the exit status is still 0.");
  return models;
}

// --physics FILE|NAME of run and check.
void add_physics_option(CLI::App& command, CommandLine& line) {
  command
      .add_option("--physics", line.physics,
                  "Attach this physics file (an MJCF world and which servo drives which joint), "
                  "or the shipped one of this NAME, e.g. openmanipulator-x (docs/physics.md)")
      ->type_name("FILE|NAME");
}

// --robots DIR of run, check and robots.
void add_robots_dir_option(CLI::App& command, CommandLine& line) {
  command
      .add_option("--robots", line.robot_dirs,
                  "Also load every *.json robot profile of DIR (repeatable); a profile replaces "
                  "the shipped one of the same name (docs/robots.md)")
      ->check(CLI::ExistingDirectory);
}

CLI::App* add_check(CLI::App& app, CommandLine& line) {
  auto* check = app.add_subcommand(
      "check", "Validate a bus config file or a robot profile and print its ports");
  auto* file = check->add_option("FILE", line.check_file, "The config file (docs/config.md)")
                   ->type_name("FILE");
  auto* robot =
      check->add_option("--robot", line.check_robot, "The robot profile NAME (dxlemu robots)")
          ->type_name("NAME");
  file->excludes(robot);
  add_physics_option(*check, line);
  add_models_option(*check, line);
  add_robots_dir_option(*check, line);
  check->footer("Give FILE or --robot NAME.");
  return check;
}

CLI::App* add_robots(CLI::App& app, CommandLine& line) {
  auto* robots = app.add_subcommand("robots",
                                    "List the robot profiles: name, ports, servos, a shipped "
                                    "physics model, title, public source");
  add_models_option(*robots, line);
  add_robots_dir_option(*robots, line);
  robots->footer("Serve one with dxlemu run --robot NAME (docs/robots.md).");
  return robots;
}

CLI::App* add_clone(CLI::App& app, CommandLine& line) {
  CloneArguments& clone = line.clone;
  auto* cmd = app.add_subcommand(
      "clone", "Scan a real bus (read only) and write the config that serves it as it is");
  cmd->add_option("PORT", clone.port, "The serial device the bus is on, e.g. /dev/ttyUSB0")
      ->required()
      ->type_name("PORT");
  cmd->add_option("--out", clone.out, "Write the config to FILE (default: stdout)")
      ->type_name("FILE");
  cmd->add_option("--name", clone.name, "The port's name in the config")->capture_default_str();
  cmd->add_option("--link", clone.link, "The symlink the cloned port gets in the config")
      ->type_name("PATH");
  cmd->add_option("--baud", clone.bauds,
                  "Only this rate, bit/s (repeatable; default: every rate a model offers, "
                  "1000000, 57600 and 115200 first)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--protocol", clone.protocols,
                  "Only this protocol: 1, 2, feetech or modbus (repeatable; default: all but "
                  "modbus, whose sweep of every address is asked for by name)")
      ->check(CLI::IsMember(wire::protocol_spellings()));
  cmd->add_option("--ids", clone.ids,
                  "The IDs the Protocol 1.0, FEETECH and Modbus sweeps ask, FIRST-LAST (2.0 finds "
                  "every ID with one broadcast Ping; Modbus asks 1 ~ 247 of them)")
      ->capture_default_str();
  cmd->add_option("--timeout-ms", clone.timeout_ms,
                  "How long to wait for a reply: 34 suits a USB adapter at its 16 ms latency "
                  "timer; 5 is plenty on a dxlemu PTY")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  add_models_option(*cmd, line);
  return cmd;
}

// run's options that belong to one robot, bound to the --robot before them by their order on
// the command line (docs/robots.md "Several robots in one daemon"). CLI11 keeps each option's
// values in the order given and every occurrence in parse_order(), so the binding walks that.
struct RobotOptions {
  const CLI::Option* robot = nullptr;
  const CLI::Option* physics = nullptr;
  const CLI::Option* hand = nullptr;
};

// Sets `line.robots`, `line.physics` and `line.hands` from run's parsed `options`. Throws
// CLI::ValidationError (a refused command line) for an option that belongs to no robot.
void bind_robot_options(const CLI::App& run, const RobotOptions& options, CommandLine& line) {
  std::vector<RobotRequest> robots;
  std::vector<std::string> physics_before;  // given before any --robot
  std::vector<std::string> hands_before;
  std::size_t robot_values = 0;
  std::size_t physics_values = 0;
  std::size_t hand_values = 0;
  for (const CLI::Option* option : run.parse_order()) {
    if (option == options.robot) {
      robots.push_back({option->results().at(robot_values++), std::nullopt, {}});
    } else if (option == options.physics) {
      const std::string& physics = option->results().at(physics_values++);
      if (robots.empty()) {
        physics_before.push_back(physics);
      } else if (robots.back().physics) {
        throw CLI::ValidationError("--physics", "given twice for robot " + robots.back().name +
                                                    ": one physics file per robot");
      } else {
        robots.back().physics = physics;
      }
    } else if (option == options.hand) {
      const std::string& hand = option->results().at(hand_values++);
      (robots.empty() ? hands_before : robots.back().hands).push_back(hand);
    }
  }
  if (robots.empty()) {
    if (physics_before.size() > 1) {
      throw CLI::ValidationError("--physics", "given twice: a daemon simulates one world");
    }
    line.physics = physics_before.empty() ? std::string() : physics_before.front();
    line.hands = std::move(hands_before);
    return;
  }
  if (robots.size() == 1) {
    // One robot: whatever is given before --robot is that robot's, as it always was.
    RobotRequest& robot = robots.front();
    if (!physics_before.empty() && (physics_before.size() > 1 || robot.physics)) {
      throw CLI::ValidationError(
          "--physics", "given twice for robot " + robot.name + ": one physics file per robot");
    }
    if (!physics_before.empty()) {
      robot.physics = physics_before.front();
    }
    robot.hands.insert(robot.hands.begin(), hands_before.begin(), hands_before.end());
  } else if (!physics_before.empty() || !hands_before.empty()) {
    const char* option = physics_before.empty() ? "--hand" : "--physics";
    throw CLI::ValidationError(option, std::string("given before the first --robot, with ") +
                                           std::to_string(robots.size()) +
                                           " robots: put it after the --robot it is for");
  }
  line.robots = std::move(robots);
}

// run's options that say which servos there are and how they speak; returns --link.
const CLI::Option* add_bus_options(CLI::App& run, CommandLine& line) {
  line.link = kDefaultLink;
  auto* config_option =
      run.add_option("--config", line.config_file,
                     "Serve the ports and servos of this config file (docs/config.md)")
          ->type_name("FILE");
  auto* servo_option =
      run.add_option(
             "--servo", line.servo_options,
             "A servo NAME:ID or a range NAME:FIRST-LAST on port dxl0 (repeatable); NAME may "
             "name a firmware, NAME@FIRMWARE (dxlemu models lists them); default " +
                 std::string(kDefaultServos))
          ->type_name("NAME:ID");
  auto* link_option =
      run.add_option("--link", line.link, "Stable symlink to port dxl0's PTY, removed on exit")
          ->type_name("PATH")
          ->capture_default_str();
  // One value per occurrence: each --robot starts the options that belong to that robot.
  auto* robot_option =
      run.add_option("--robot",
                     "Serve the bus of this robot profile (repeatable: several robots in one "
                     "daemon; dxlemu robots lists them; docs/robots.md); --link then names its "
                     "port's link when it is one robot with one port")
          ->type_name("NAME")
          ->take_all()
          ->allow_extra_args(false);
  auto* physics_option =
      run.add_option("--physics",
                     "Attach this physics file (an MJCF world and which servo drives which "
                     "joint), or the shipped one of this NAME, e.g. openmanipulator-x, to the "
                     "--robot before it, or to the bus (docs/physics.md)")
          ->type_name("FILE|NAME")
          ->take_all()
          ->allow_extra_args(false);
  auto* hand_option =
      run.add_option("--hand",
                     "A virtual hand moving the joints of the --robot before it (repeatable), or "
                     "of the bus without --robot")
          ->type_name("HAND")
          ->take_all()
          ->allow_extra_args(false);
  servo_option->excludes(config_option);
  link_option->excludes(config_option);
  robot_option->excludes(config_option);
  robot_option->excludes(servo_option);
  run.callback([&run, &line, options = RobotOptions{robot_option, physics_option, hand_option}] {
    bind_robot_options(run, options, line);
  });
  add_models_option(run, line);
  add_robots_dir_option(run, line);
  run.add_option("--baud", line.baud,
                 "Set every servo's Baud Rate to BPS (an error if a model cannot do it); "
                 "default: each model's factory rate or the config's")
      ->type_name("BPS");
  run.add_option("--protocol", line.protocol,
                 "Make every servo speak this protocol: 1, 2 (DYNAMIXEL), modbus (Modbus RTU) or "
                 "feetech; sets Protocol Type on the models that have it (an error for a model "
                 "that cannot speak it); default: factory")
      ->check(CLI::IsMember(wire::protocol_spellings()));
  return link_option;
}

// run's options that say how the daemon runs: time, files, the control socket, faults.
void add_daemon_options(CLI::App& run, CommandLine& line) {
  RunOptions& options = line.options;
  line.timing = "realtime";
  run.add_option("--timing", line.timing,
                 "realtime: replies at the modelled time; fast: replies at once; manual: "
                 "simulated time stands still, replies at once (docs/timing.md)")
      ->check(CLI::IsMember({"realtime", "fast", "manual"}))
      ->capture_default_str();
  run.add_option("--state", options.state,
                 "Keep every servo's EEPROM in FILE across restarts (written atomically)")
      ->type_name("FILE");
  run.add_option("--control", options.control,
                 "The control API's Unix socket (docs/control-api.md); default: "
                 "$XDG_RUNTIME_DIR or /tmp, dxlemu-PID.sock")
      ->type_name("PATH");
  run.add_option("--web", line.web,
                 "Serve the web interface on PORT of ADDR (default 127.0.0.1; 0: any free "
                 "port); the URL to open, with its access token, is printed (docs/web.md)")
      ->type_name("[ADDR:]PORT")
      ->check(CLI::Validator(
          [](const std::string& text) {
            try {
              parse_web_address(text);
              return std::string();
            } catch (const std::invalid_argument& e) {
              return std::string(e.what());
            }
          },
          ""));
  run.add_flag("--web-read-only", options.web_read_only,
               "The web interface only shows: every change through it is refused");
  run.add_option("--trace", options.trace,
                 "Write every packet both ways, decoded, as JSON lines to FILE (docs/trace.md)")
      ->type_name("FILE");
  run.add_option("--pcap", options.pcap,
                 "Write every packet both ways to FILE as a pcap capture for Wireshark with "
                 "scripts/dxlemu.lua (docs/pcap.md)")
      ->type_name("FILE");
  run.add_option("--scenario", options.scenario,
                 "Run the timeline of faults and conditions in FILE (docs/faults.md)");
  run.add_option("--pty-handover-us", line.handover_us,
                 "Realtime timing: the PTY's hand-over delay to take off reply times, in us "
                 "(default: measured at start; 0: none; docs/timing.md)")
      ->check(CLI::Range(0, 10000));
  line.late_reply_limit_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(bus::LateReplyPolicy{}.drop_after)
          .count();
  run.add_option("--late-reply-limit-ms", line.late_reply_limit_ms,
                 "Drop a reply, instead of sending it, when the machine made it later than this "
                 "against its modelled time (0: never drop; docs/timing.md \"Late replies\")")
      ->check(CLI::Range(0, 60000))
      ->capture_default_str();
  run.add_option("--realtime-priority", options.realtime_priority,
                 "Run the daemon's thread under SCHED_FIFO at this priority (1 ~ 99; 10 is "
                 "plenty) with its memory locked, where the system permits it "
                 "(docs/timing.md \"Late replies\")")
      ->check(CLI::Range(1, 99));
  run.add_option("--adapter-latency-ms", options.adapter_latency_ms,
                 "Hand replies over as a USB serial adapter would, with this latency timer in ms "
                 "(a U2D2's default: 16); 0: at once; a port's \"adapter_latency_ms\" overrides "
                 "it (docs/timing.md)")
      ->check(CLI::Range(0, kMaxAdapterLatencyMs))
      ->capture_default_str();
  run.add_option("--adapter-chip", options.adapter_chip,
                 "The adapter's chip, for its USB packet size: ft232h (a U2D2, 510 data bytes) "
                 "or ft232r (62)")
      ->check(CLI::Validator(
          [](const std::string& chip) {
            return adapter_packet_data(chip)
                       ? std::string()
                       : "unknown chip \"" + chip + "\" (known: " + adapter_chip_names() + ")";
          },
          "CHIP"))
      ->capture_default_str();
  run.add_option("--seed", options.seed,
                 "Seeds the random choices of fault injection (docs/faults.md); default 1");
  line.tick_hz = kDefaultTickHz;
  run.add_option("--tick-hz", line.tick_hz,
                 "Motion model ticks per second of simulated time (docs/motion.md)")
      ->check(CLI::Range(kMinTickHz, kMaxTickHz))
      ->capture_default_str();
  line.log_level = "info";
  run.add_option("--log-level", line.log_level, "Messages on stderr: error, warn, info or debug")
      ->check(CLI::IsMember({"error", "warn", "info", "debug"}))
      ->capture_default_str();
}

CLI::App* add_ctl(CLI::App& app, CommandLine& line) {
  CtlArguments& ctl_arguments = line.ctl;
  auto* ctl = app.add_subcommand(
      "ctl", "Send one request to a running emulator's control API and print the result as JSON");
  ctl->add_option("--control", ctl_arguments.control,
                  "The daemon's control socket; default: $DXLEMU_CONTROL, else the only live "
                  "dxlemu-*.sock in $XDG_RUNTIME_DIR or /tmp")
      ->type_name("PATH");
  ctl_arguments.timeout_s = kDefaultCtlTimeoutS;
  ctl->add_option("--timeout", ctl_arguments.timeout_s, "Seconds to wait for the reply")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  ctl->add_option("COMMAND", ctl_arguments.command,
                  "A control API command: list, get, set, clock.step, stats, help... "
                  "(docs/control-api.md)")
      ->required();
  ctl->add_option("ARG", ctl_arguments.args,
                  "key=value (value read as JSON when it parses, else a string), or a JSON object "
                  "whose members are added, e.g. servo=1 item=goal_position value=2048");
  ctl->footer(
      "Exit status: 0 done (the result is printed), 1 refused (the error is printed), "
      "2 bad arguments or no daemon to talk to.");
  return ctl;
}

CLI::App* add_exec(CLI::App& app, CommandLine& line) {
  ExecArguments& arguments = line.exec;
  auto* exec = app.add_subcommand(
      "exec",
      "Run a client with the preload library that makes dxlemu's PTYs behave like a USB "
      "adapter (tcflush keeps written bytes; TIOCGSERIAL, modem lines, RS-485 work)");
  // One value per occurrence: a vector option would otherwise swallow COMMAND too.
  exec->add_option("--port", arguments.ports, "A dxlemu PTY or its link to protect (repeatable)")
      ->type_name("PATH")
      ->allow_extra_args(false);
  exec->add_option("--control", arguments.controls,
                   "Protect every port of the daemon at this control socket (repeatable)")
      ->type_name("SOCKET")
      ->allow_extra_args(false);
  // COMMAND is what follows -- (exec_split), or without --, everything from the first argument
  // that is not one of these options, its own options included (exec_command).
  exec->prefix_command();
  exec->footer(
      "Usage: dxlemu exec [--port PATH]... [--control SOCKET]... -- COMMAND [ARG]...\n"
      "With neither option, the ports of every running dxlemu whose control socket is in "
      "$XDG_RUNTIME_DIR or /tmp (dxlemu-*.sock). COMMAND runs with LD_PRELOAD and "
      "DXLEMU_PTYS set (docs/exec.md). Exit status: COMMAND's, 128+N if signal N killed it; "
      "125 when dxlemu exec fails (no PTY found, no preload library), 126 COMMAND cannot be "
      "run, 127 COMMAND not found.");
  return exec;
}

}  // namespace

TimingMode timing_mode(const std::string& name) {
  return kTimingModes.at(name);
}

ModelFilter model_filter(const ModelsArguments& models) {
  ModelFilter filter;
  if (!models.family.empty()) {
    filter.family = model::family_from_name(models.family);
    if (!filter.family) {
      throw std::invalid_argument("--family: " + unknown_family(models.family));
    }
  }
  if (models.protocol) {
    filter.protocol = wire::protocol_from_spelling(*models.protocol);
  }
  filter.name_fragment = models.name;
  return filter;
}

std::vector<std::string> exec_command(const CLI::App& exec, std::vector<std::string> after_dashes) {
  std::vector<std::string> command = exec.remaining();
  command.insert(command.end(), after_dashes.begin(), after_dashes.end());
  if (command.empty()) {
    throw std::invalid_argument("no COMMAND to run (dxlemu exec [OPTIONS] -- COMMAND [ARG]...)");
  }
  return command;
}

Subcommands define_command_line(CLI::App& app, CommandLine& line) {
  app.set_version_flag("--version", std::string("dxlemu ") + kVersion);
  app.require_subcommand(0, 1);
  app.footer(
      "Documentation: README.md and docs/ (config format: docs/config.md, robot profiles: "
      "docs/robots.md)");
  Subcommands subcommands;
  subcommands.models = add_models(app, line);
  subcommands.check = add_check(app, line);
  subcommands.robots = add_robots(app, line);
  subcommands.run = app.add_subcommand("run", "Serve buses of virtual servos on pseudo-terminals");
  subcommands.run_link = add_bus_options(*subcommands.run, line);
  add_daemon_options(*subcommands.run, line);
  subcommands.ctl = add_ctl(app, line);
  subcommands.exec = add_exec(app, line);
  subcommands.clone = add_clone(app, line);
  return subcommands;
}

}  // namespace dxlemu::app
