// dxlemu: a DYNAMIXEL servo-bus emulator. `dxlemu run` serves a bus of virtual servos on a
// pseudo-terminal; `dxlemu models` lists the model library.
#include <CLI/CLI.hpp>
#include <functional>
#include <iomanip>
#include <iostream>

#include "app/emulator.hpp"
#include "app/model_library.hpp"
#include "dxlemu/version.hpp"
#include "model/model_error.hpp"

namespace {

// Exit status for refused input (bad model file, bad config), as documented in README.md.
constexpr int kExitBadInput = 2;

// The default bus (README): three XM430-W350 at factory settings, IDs 1 to 3, on dxl0.
constexpr const char* kDefaultServos = "xm430-w350:1-3";
constexpr const char* kDefaultLink = "/tmp/dxlemu-dxl0";
constexpr int kMaxServoId = 252;

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
  if (first < 0 || last > kMaxServoId || first > last) {
    throw std::invalid_argument("--servo " + text + ": IDs must lie in 0 ~ 252, first <= last");
  }
  std::vector<dxlemu::app::ServoConfig> out;
  for (int id = first; id <= last; ++id) {
    out.push_back({name, static_cast<std::uint8_t>(id), {}});
  }
  return out;
}

// --baud BPS: the Baud Rate item value that selects BPS on `spec`, or an error naming what the
// model offers.
std::int64_t baud_index(const dxlemu::model::ModelSpec& spec, std::uint32_t bps) {
  std::string offered;
  for (const auto& b : spec.baud_rates) {
    if (b.bps == bps) {
      return b.index;
    }
    offered += (offered.empty() ? "" : ", ") + std::to_string(b.bps);
  }
  throw std::invalid_argument("--baud " + std::to_string(bps) + ": " + spec.name +
                              " cannot do it (it offers " + offered + ")");
}

// --protocol N: the Protocol Type item (Protocol Version on MX-64/106(2.0)); models without it
// must already speak N.
std::optional<std::pair<std::string, std::int64_t>> protocol_item(
    const dxlemu::model::ModelSpec& spec, int protocol) {
  for (const char* key : {"protocol_type", "protocol_version"}) {
    if (spec.find(key) != nullptr) {
      return std::pair<std::string, std::int64_t>{key, protocol};
    }
  }
  if (static_cast<int>(spec.protocols.front()) != protocol) {
    throw std::invalid_argument("--protocol " + std::to_string(protocol) + ": " + spec.name +
                                " cannot speak it");
  }
  return std::nullopt;
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

std::string protocols_text(const dxlemu::model::ModelSpec& spec) {
  std::string out;
  for (const auto p : spec.protocols) {
    out += (out.empty() ? "" : ",") + std::string(p == dxlemu::wire::Protocol::V1 ? "1.0" : "2.0");
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dxlemu: emulates a chain of ROBOTIS DYNAMIXEL servos on a pseudo-terminal"};
  app.set_version_flag("--version", std::string("dxlemu ") + dxlemu::kVersion);
  app.require_subcommand(0, 1);

  std::vector<std::string> model_dirs;
  auto* models =
      app.add_subcommand("models", "List the model library: name, model number, protocols");
  models
      ->add_option("--models", model_dirs,
                   "Also load every *.json model file of DIR (repeatable); a file replaces the "
                   "shipped model of the same name")
      ->check(CLI::ExistingDirectory);

  std::vector<std::string> servo_options;
  std::string link = kDefaultLink;
  auto* run = app.add_subcommand("run", "Serve a bus of virtual servos on a pseudo-terminal");
  run->add_option("--servo", servo_options,
                  "A servo NAME:ID or a range NAME:FIRST-LAST on port dxl0 (repeatable); default " +
                      std::string(kDefaultServos));
  run->add_option("--link", link, "Stable symlink to the port's PTY, removed on exit")
      ->capture_default_str();
  run->add_option("--models", model_dirs, "Also load every *.json model file of DIR (repeatable)")
      ->check(CLI::ExistingDirectory);
  std::optional<std::uint32_t> baud;
  std::optional<int> protocol;
  run->add_option("--baud", baud,
                  "Set every servo's Baud Rate to BPS (an error if a model cannot do it); "
                  "default: each model's factory rate");
  run->add_option("--protocol", protocol,
                  "Set Protocol Type to 1 or 2 on the models that have it; default: factory")
      ->check(CLI::IsMember({1, 2}));

  CLI11_PARSE(app, argc, argv);

  if (run->parsed()) {
    return run_command([&] {
      const auto library = load_library(model_dirs);
      dxlemu::app::PortConfig port{"dxl0", std::filesystem::path(link), {}};
      if (servo_options.empty()) {
        servo_options.emplace_back(kDefaultServos);
      }
      for (const std::string& option : servo_options) {
        for (auto& servo : parse_servo_option(option)) {
          const auto spec = library.find(servo.model);
          if (spec && baud) {
            servo.items.emplace_back("baud_rate", baud_index(*spec, *baud));
          }
          if (spec && protocol) {
            if (auto item = protocol_item(*spec, *protocol)) {
              servo.items.push_back(std::move(*item));
            }
          }
          port.servos.push_back(std::move(servo));
        }
      }
      dxlemu::app::Emulator emulator(library, {port});
      emulator.run(std::cout);
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
