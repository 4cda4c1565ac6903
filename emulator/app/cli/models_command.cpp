#include "app/cli/models_command.hpp"

#include <iomanip>
#include <iostream>

#include "app/cli/libraries.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {
namespace {

std::string protocols_text(const model::ModelSpec& spec) {
  std::string out;
  for (const auto p : spec.protocols) {
    if (!out.empty()) {
      out += ',';
    }
    out += wire::protocol_name(p);
  }
  return out;
}

// The filters given to `dxlemu models`, as the user wrote them.
std::string filters_text(const ModelsArguments& models) {
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

}  // namespace

void list_models(const std::vector<std::string>& model_dirs, const ModelsArguments& models) {
  const auto filter = model_filter(models);
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
              << protocols_text(*spec) << model::family_name(spec->family) << "\n";
    // Its other firmware, by the name --servo and a config take (NAME@FIRMWARE).
    for (const auto& variant : library.variants_of(spec->name)) {
      std::cout << std::setw(18) << variant->name << std::setw(8) << variant->model_number
                << std::setw(10) << protocols_text(*variant) << model::family_name(variant->family)
                << "\n";
    }
  }
}

}  // namespace dxlemu::app
