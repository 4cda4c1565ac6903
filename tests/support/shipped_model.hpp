#pragma once

#include <memory>
#include <string>

#include "model/model_spec.hpp"

namespace dxlemu::test {

/// The shipped model `name` from models/ ("xm430-w350"), loaded with the real loader.
std::shared_ptr<const model::ModelSpec> shipped_model(const std::string& name);

}  // namespace dxlemu::test
