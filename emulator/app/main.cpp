// dxlemu: a DYNAMIXEL servo-bus emulator. `dxlemu run` serves buses of virtual servos on
// pseudo-terminals; `dxlemu models` lists the model library; `dxlemu check` validates a config;
// `dxlemu ctl` sends one request to a running emulator's control API.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>

#include "app/bus_config.hpp"
#include "app/ctl_request.hpp"
#include "app/emulator.hpp"
#include "app/log.hpp"
#include "app/model_library.hpp"
#include "dxlemu/version.hpp"
#include "io/control_client.hpp"
#include "model/model_error.hpp"

namespace {

// Exit status for refused input (bad model file, bad config), as documented in README.md.
constexpr int kExitBadInput = 2;

// How long `dxlemu ctl` waits for a reply by default: long enough for a clock.step of an hour.
constexpr double kDefaultCtlTimeoutS = 60;

// The default bus (README): three XM430-W350 at factory settings, IDs 1 to 3, on dxl0.
constexpr const char* kDefaultServos = "xm430-w350:1-3";
constexpr const char* kDefaultLink = "/tmp/dxlemu-dxl0";

// --tick-hz: 1 kHz by default (docs/motion.md); 10 Hz ~ 10 kHz accepted.
constexpr int kDefaultTickHz = 1000;
constexpr int kMinTickHz = 10;
constexpr int kMaxTickHz = 10000;

// --timing names (docs/timing.md).
const std::map<std::string, dxlemu::app::TimingMode> kTimingModes = {
    {"realtime", dxlemu::app::TimingMode::Realtime},
    {"fast", dxlemu::app::TimingMode::Fast},
    {"manual", dxlemu::app::TimingMode::Manual}};

// "NAME:ID" or "NAME:FIRST-LAST" (model names may contain ':'-free punctuation such as '+').
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
struct CtlArguments {
  std::optional<std::filesystem::path> control;
  std::string command;
  std::vector<std::string> args;
  double timeout_s = 0;
};

int run_ctl(const CtlArguments& ctl) {
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

std::string protocols_text(const dxlemu::model::ModelSpec& spec) {
  std::string out;
  for (const auto p : spec.protocols) {
    if (!out.empty()) {
      out += ',';
    }
    out += p == dxlemu::wire::Protocol::V1 ? "1.0" : "2.0";
  }
  return out;
}

}  // namespace

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

int main(int argc, char** argv) {
  CLI::App app{"dxlemu: emulates chains of ROBOTIS DYNAMIXEL servos on pseudo-terminals"};
  app.set_version_flag("--version", std::string("dxlemu ") + dxlemu::kVersion);
  app.require_subcommand(0, 1);
  app.footer("Documentation: README.md and docs/ (config format: docs/config.md)");

  std::vector<std::string> model_dirs;
  auto* models =
      app.add_subcommand("models", "List the model library: name, model number, protocols");
  models
      ->add_option("--models", model_dirs,
                   "Also load every *.json model file of DIR (repeatable); a file replaces the "
                   "shipped model of the same name")
      ->check(CLI::ExistingDirectory);

  std::string check_file;
  auto* check = app.add_subcommand("check", "Validate a bus config file and print its ports");
  check->add_option("FILE", check_file, "The config file (docs/config.md)")
      ->required()
      ->type_name("FILE");
  check->add_option("--models", model_dirs, "Also load every *.json model file of DIR (repeatable)")
      ->check(CLI::ExistingDirectory);

  std::vector<std::string> servo_options;
  std::string link = kDefaultLink;
  std::string config_file;
  auto* run = app.add_subcommand("run", "Serve buses of virtual servos on pseudo-terminals");
  auto* config_option =
      run->add_option("--config", config_file,
                      "Serve the ports and servos of this config file (docs/config.md)")
          ->type_name("FILE");
  auto* servo_option =
      run->add_option(
             "--servo", servo_options,
             "A servo NAME:ID or a range NAME:FIRST-LAST on port dxl0 (repeatable); default " +
                 std::string(kDefaultServos))
          ->type_name("NAME:ID");
  auto* link_option =
      run->add_option("--link", link, "Stable symlink to port dxl0's PTY, removed on exit")
          ->type_name("PATH")
          ->capture_default_str();
  servo_option->excludes(config_option);
  link_option->excludes(config_option);
  run->add_option("--models", model_dirs, "Also load every *.json model file of DIR (repeatable)")
      ->check(CLI::ExistingDirectory);
  std::optional<std::uint32_t> baud;
  std::optional<int> protocol;
  run->add_option("--baud", baud,
                  "Set every servo's Baud Rate to BPS (an error if a model cannot do it); "
                  "default: each model's factory rate or the config's")
      ->type_name("BPS");
  run->add_option("--protocol", protocol,
                  "Set Protocol Type to 1 or 2 on the models that have it; default: factory")
      ->check(CLI::IsMember({1, 2}));
  dxlemu::app::RunOptions options;
  std::string timing = "realtime";
  run->add_option("--timing", timing,
                  "realtime: replies at the modelled time; fast: replies at once; manual: "
                  "simulated time stands still, replies at once (docs/timing.md)")
      ->check(CLI::IsMember({"realtime", "fast", "manual"}))
      ->capture_default_str();
  run->add_option("--state", options.state,
                  "Keep every servo's EEPROM in FILE across restarts (written atomically)")
      ->type_name("FILE");
  run->add_option("--control", options.control,
                  "The control API's Unix socket (docs/control-api.md); default: "
                  "$XDG_RUNTIME_DIR or /tmp, dxlemu-PID.sock")
      ->type_name("PATH");
  run->add_option("--trace", options.trace,
                  "Write every packet both ways, decoded, as JSON lines to FILE (docs/trace.md)")
      ->type_name("FILE");
  run->add_option("--pcap", options.pcap,
                  "Write every packet both ways to FILE as a pcap capture for Wireshark with "
                  "scripts/dxlemu.lua (docs/pcap.md)")
      ->type_name("FILE");
  run->add_option("--scenario", options.scenario,
                  "Run the timeline of faults and conditions in FILE (docs/faults.md)");
  std::optional<std::int64_t> handover_us;
  run->add_option("--pty-handover-us", handover_us,
                  "Realtime timing: the PTY's hand-over delay to take off reply times, in us "
                  "(default: measured at start; 0: none; docs/timing.md)")
      ->check(CLI::Range(0, 10000));
  run->add_option("--seed", options.seed,
                  "Seeds the random choices of fault injection (docs/faults.md); default 1");
  int tick_hz = kDefaultTickHz;
  run->add_option("--tick-hz", tick_hz,
                  "Motion model ticks per second of simulated time (docs/motion.md)")
      ->check(CLI::Range(kMinTickHz, kMaxTickHz))
      ->capture_default_str();
  std::string log_level = "info";
  run->add_option("--log-level", log_level, "Messages on stderr: error, warn, info or debug")
      ->check(CLI::IsMember({"error", "warn", "info", "debug"}))
      ->capture_default_str();

  CtlArguments ctl_arguments;
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is refused input like a bad config.
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  if (run->parsed()) {
    return run_command([&] {
      dxlemu::app::set_log_level(*dxlemu::app::parse_log_level(log_level));
      options.timing = kTimingModes.at(timing);
      options.tick = std::chrono::nanoseconds(std::chrono::seconds(1)) / tick_hz;
      if (handover_us) {
        options.pty_handover = std::chrono::microseconds(*handover_us);
      }
      const auto library = load_library(model_dirs);
      dxlemu::app::BusConfig config;
      if (!config_file.empty()) {
        config = dxlemu::app::read_config(config_file, library);
      } else {
        dxlemu::app::PortConfig port{"dxl0", std::filesystem::path(link), {}};
        if (servo_options.empty()) {
          servo_options.emplace_back(kDefaultServos);
        }
        for (const std::string& option : servo_options) {
          for (auto& servo : parse_servo_option(option)) {
            port.servos.push_back(std::move(servo));
          }
        }
        config.ports.push_back(std::move(port));
      }
      apply_bus_options(config, library, baud, protocol);
      dxlemu::app::Emulator emulator(library, config, options);
      emulator.run(std::cout);
    });
  }
  if (ctl->parsed()) {
    return run_ctl(ctl_arguments);
  }
  if (check->parsed()) {
    return run_command([&] {
      const auto library = load_library(model_dirs);
      const auto config = dxlemu::app::read_config(check_file, library);
      std::cout << check_file << ": ok\n";
      for (const auto& port : config.ports) {
        std::cout << "  " << port.name << ": " << port.servos.size()
                  << (port.servos.size() == 1 ? " servo" : " servos");
        if (port.link) {
          std::cout << " at " << port.link->string();
        }
        std::cout << "\n";
      }
    });
  }
  if (models->parsed()) {
    return run_command([&] {
      const auto library = load_library(model_dirs);
      std::cout << std::left << std::setw(18) << "NAME" << std::setw(8) << "NUMBER" << std::setw(10)
                << "PROTOCOLS"
                << "FAMILY\n";
      for (const auto& [name, spec] : library.models()) {
        std::cout << std::setw(18) << name << std::setw(8) << spec->model_number << std::setw(10)
                  << protocols_text(*spec) << dxlemu::model::family_name(spec->family) << "\n";
      }
    });
  }
  // No subcommand: say what there is.
  std::cout << app.help();
  return 0;
}
