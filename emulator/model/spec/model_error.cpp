#include "model/spec/model_error.hpp"

#include <utility>

namespace dxlemu::model {

ModelError::ModelError(std::string origin, std::string pointer, std::string reason)
    : std::runtime_error(origin + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " +
                         reason),
      origin_(std::move(origin)),
      pointer_(std::move(pointer)),
      reason_(std::move(reason)) {}

}  // namespace dxlemu::model
