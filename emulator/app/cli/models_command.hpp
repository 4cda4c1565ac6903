#pragma once

#include <string>
#include <vector>

#include "app/cli/command_line.hpp"

namespace dxlemu::app {

/// `dxlemu models`: one line per model of the library (the shipped models and the --models
/// directories `model_dirs`) that the filters let through, with its other firmware below it. None
/// is not an error (the library was read; it has no such model): stderr says so. Throws
/// model::ModelError for a bad model file, std::invalid_argument for a bad filter.
void list_models(const std::vector<std::string>& model_dirs, const ModelsArguments& models);

}  // namespace dxlemu::app
