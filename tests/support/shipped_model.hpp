#pragma once

#include <memory>
#include <string>
#include <vector>

#include "model/spec/model_spec.hpp"

namespace dxlemu::test {

/// The shipped model `name` from models/ ("xm430-w350"), loaded with the real loader.
std::shared_ptr<const model::ModelSpec> shipped_model(const std::string& name);

/// Every model models/catalog.json lists, in its order, each loaded as shipped_model() does.
std::vector<std::shared_ptr<const model::ModelSpec>> catalog_models();

}  // namespace dxlemu::test
