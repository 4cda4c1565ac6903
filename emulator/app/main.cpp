// dxlemu: a DYNAMIXEL servo-bus emulator. The daemon (`dxlemu run`) comes with issue 5; today the
// program lists its model library and reports its version.
#include <CLI/CLI.hpp>
#include <iomanip>
#include <iostream>

#include "app/model_library.hpp"
#include "dxlemu/version.hpp"
#include "model/model_error.hpp"

namespace {

// Exit status for refused input (bad model file, bad config), as documented in README.md.
constexpr int kExitBadInput = 2;

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

  CLI11_PARSE(app, argc, argv);

  if (models->parsed()) {
    try {
      const auto library = dxlemu::app::ModelLibrary::load(
          dxlemu::app::shipped_models_dir(),
          std::vector<std::filesystem::path>(model_dirs.begin(), model_dirs.end()));
      std::cout << std::left << std::setw(18) << "NAME" << std::setw(8) << "NUMBER" << std::setw(10)
                << "PROTOCOLS"
                << "FAMILY\n";
      for (const auto& [name, spec] : library.models()) {
        std::cout << std::setw(18) << name << std::setw(8) << spec->model_number << std::setw(10)
                  << protocols_text(*spec) << dxlemu::model::family_name(spec->family) << "\n";
      }
    } catch (const dxlemu::model::ModelError& e) {
      std::cerr << "dxlemu: " << e.what() << "\n";
      return kExitBadInput;
    }
    return 0;
  }
  std::cout << "dxlemu " << dxlemu::kVersion
            << ": the emulator daemon is not built yet; `dxlemu models` lists the model library.\n";
  return 0;
}
