#pragma once

#include "app/config/model_library.hpp"

namespace dxlemu::test {

/// The shipped model library (models/ of the source tree), loaded once per test program.
inline const app::ModelLibrary& shipped_models() {
  static const app::ModelLibrary library = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  return library;
}

}  // namespace dxlemu::test
