#include "app/cli/models_command.hpp"

#include <iomanip>
#include <iostream>

#include "app/cli/libraries.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {
namespace {

// Column widths of the listing; each holds its longest entry and a space ("2.0,modbus").
constexpr int kNameWidth = 18;
constexpr int kNumberWidth = 8;
constexpr int kProtocolsWidth = 12;

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
  const auto row = [](const model::ModelSpec& spec) {
    std::cout << std::setw(kNameWidth) << spec.name << std::setw(kNumberWidth) << spec.model_number
              << std::setw(kProtocolsWidth) << protocols_text(spec)
              << model::family_name(spec.family) << "\n";
  };
  std::cout << std::left << std::setw(kNameWidth) << "NAME" << std::setw(kNumberWidth) << "NUMBER"
            << std::setw(kProtocolsWidth) << "PROTOCOLS"
            << "FAMILY\n";
  for (const auto& spec : listed) {
    row(*spec);
    // Its other firmware, by the name --servo and a config take (NAME@FIRMWARE).
    for (const auto& variant : library.variants_of(spec->name)) {
      row(*variant);
    }
  }
}

}  // namespace dxlemu::app
