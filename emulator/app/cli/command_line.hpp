#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/exec_setup.hpp"
#include "app/config/model_library.hpp"
#include "app/config/robot_request.hpp"
#include "app/daemon/run_options.hpp"

namespace dxlemu::app {

/// `dxlemu ctl`'s arguments (docs/control-api.md "From a shell: dxlemu ctl").
struct CtlArguments {
  std::optional<std::filesystem::path> control;
  std::string command;
  std::vector<std::string> args;
  double timeout_s = 0;
};

/// `dxlemu models`' filters, as given (README.md "Running the emulator").
struct ModelsArguments {
  std::string family;                   ///< --family; empty: any
  std::optional<std::string> protocol;  ///< --protocol: "1", "2", "feetech" or "modbus"
  std::string name;                     ///< --name, a fragment of the name or title; empty: any
};

/// `dxlemu clone`'s arguments (docs/robots.md "Cloning a real bus").
struct CloneArguments {
  std::string port;                    ///< PORT: the serial device
  std::string out;                     ///< --out FILE; empty: stdout
  std::string name = "dxl0";           ///< --name: the port's name in the config
  std::string link;                    ///< --link: the cloned port's link in the config
  std::vector<std::uint32_t> bauds;    ///< --baud, repeatable; empty: every rate of the library
  std::vector<std::string> protocols;  ///< --protocol: wire::protocol_spellings(); empty: see clone
  std::string ids = "0-253";           ///< --ids FIRST-LAST, for the 1.0 and FEETECH sweep
  int timeout_ms = 34;                 ///< --timeout-ms
};

/// Everything the command line can say, as parsed: the defaults until then.
struct CommandLine {
  /// --models of every subcommand.
  std::vector<std::string> model_dirs;
  /// --robots of run, check and robots: more robot profile directories (docs/robots.md).
  std::vector<std::string> robot_dirs;
  /// check FILE; empty with check --robot.
  std::string check_file;
  /// check --robot NAME; empty with check FILE.
  std::string check_robot;
  /// --physics of check, and of run without --robot: a physics file, or a shipped one's name;
  /// empty: none. With --robot it is in `robots`.
  std::string physics;
  // run: the bus.
  std::vector<std::string> servo_options;  ///< --servo, before parse_servo_option
  std::string link;                        ///< --link
  std::string config_file;                 ///< --config; empty: --servo and --link
  /// Each --robot in command-line order, with the --physics and --hand bound to it (those after
  /// it; with one robot, those before it too); empty: none (docs/robots.md).
  std::vector<RobotRequest> robots;
  /// --hand of run without --robot (with --config or --servo), each value as given.
  std::vector<std::string> hands;
  std::optional<std::uint32_t> baud;    ///< --baud
  std::optional<std::string> protocol;  ///< --protocol: a wire::protocol_spellings() entry
  // run: the daemon.
  RunOptions options;  ///< what --state, --control, --trace, --pcap, --scenario, --seed set
  std::string timing;  ///< --timing, before kTimingModes
  std::optional<std::int64_t> handover_us;  ///< --pty-handover-us
  std::int64_t late_reply_limit_ms = 0;     ///< --late-reply-limit-ms
  int tick_hz = 0;                          ///< --tick-hz
  std::string log_level;                    ///< --log-level
  std::string web;                          ///< --web, before parse_web_address; empty: none
  CtlArguments ctl;
  ModelsArguments models;
  ExecArguments exec;
  CloneArguments clone;
};

/// The subcommands, to ask which one was given.
struct Subcommands {
  CLI::App* models = nullptr;
  CLI::App* check = nullptr;
  CLI::App* run = nullptr;
  CLI::App* ctl = nullptr;
  CLI::App* exec = nullptr;
  CLI::App* clone = nullptr;
  CLI::App* robots = nullptr;
  /// run's --link, to ask whether it was given (it has a default).
  const CLI::Option* run_link = nullptr;
};

/// The servos `dxlemu run` serves without --servo or --config (README): three XM430-W350 at
/// factory settings, IDs 1 to 3, on dxl0.
inline constexpr const char* kDefaultServos = "xm430-w350:1-3";

/// The --timing names (docs/timing.md).
TimingMode timing_mode(const std::string& name);

/// The filter `models` asks for: the family named (already checked by the parser; an unknown
/// one throws std::invalid_argument naming the known ones), the protocol, the name fragment.
ModelFilter model_filter(const ModelsArguments& models);

/// COMMAND of a parsed `dxlemu exec`: its remaining arguments (a COMMAND given without --), then
/// `after_dashes` (exec_split's, app/cli/exec_setup.hpp). Throws std::invalid_argument when there
/// is none.
std::vector<std::string> exec_command(const CLI::App& exec, std::vector<std::string> after_dashes);

/// Defines dxlemu's options and subcommands on `app`, each parsed into `line` (which must
/// outlive `app`); sets `line`'s defaults. The order here is the order of --help.
Subcommands define_command_line(CLI::App& app, CommandLine& line);

}  // namespace dxlemu::app
