// dxlemu: a DYNAMIXEL servo-bus emulator. `dxlemu run` serves buses of virtual servos on
// pseudo-terminals; `dxlemu models` lists the model library; `dxlemu robots` the robot profiles;
// `dxlemu check` validates a config or a profile;
// `dxlemu ctl` sends one request to a running emulator's control API; `dxlemu exec` runs a client
// with the preload library that makes the emulator's PTYs behave like a USB adapter.
// `dxlemu clone` scans a real bus and writes the config that serves it.
#include <CLI/CLI.hpp>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/cli/check_command.hpp"
#include "app/cli/clone_command.hpp"
#include "app/cli/command_line.hpp"
#include "app/cli/ctl_command.hpp"
#include "app/cli/exec_command.hpp"
#include "app/cli/exit_status.hpp"
#include "app/cli/libraries.hpp"
#include "app/cli/models_command.hpp"
#include "app/cli/robots_command.hpp"
#include "app/cli/run_command.hpp"

namespace dxlemu::app {
namespace {

// Parses the command line and runs the subcommand it names; returns the exit status.
int dispatch(int argc, char** argv) {
  CLI::App app{"dxlemu: emulates chains of ROBOTIS DYNAMIXEL servos on pseudo-terminals"};
  CommandLine line;
  const Subcommands given = define_command_line(app, line);
  std::vector<std::string> after_dashes;
  const int parsed_argc = exec_split(argc, argv, after_dashes);
  try {
    app.parse(parsed_argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is refused input like a bad config.
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }
  if (given.run->parsed()) {
    return exit_status_of([&] { serve(line, given.run_link->count() > 0); });
  }
  if (given.ctl->parsed()) {
    return run_ctl(line.ctl);
  }
  if (given.exec->parsed()) {
    try {
      line.exec.command = exec_command(*given.exec, after_dashes);
    } catch (const std::invalid_argument& e) {
      std::cerr << "dxlemu exec: " << e.what() << "\n";
      return kExitExecFailed;
    }
    return run_exec(line.exec);
  }
  if (given.clone->parsed()) {
    return exit_status_of(
        [&] { clone_bus(line.clone, load_library(line.model_dirs), std::cout, std::cerr); });
  }
  if (given.check->parsed()) {
    return exit_status_of([&] { check_config(line); });
  }
  if (given.robots->parsed()) {
    return exit_status_of([&] { list_robots(line); });
  }
  if (given.models->parsed()) {
    return exit_status_of([&] { list_models(line.model_dirs, line.models); });
  }
  // No subcommand: say what there is.
  std::cout << app.help();
  return 0;
}

}  // namespace
}  // namespace dxlemu::app

int main(int argc, char** argv) {
  return dxlemu::app::dispatch(argc, argv);
}
