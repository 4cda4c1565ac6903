#include "app/cli/exit_status.hpp"

#include <exception>
#include <iostream>
#include <stdexcept>

#include "model/spec/model_error.hpp"

namespace dxlemu::app {

int exit_status_of(const std::function<void()>& body) {
  try {
    body();
    return 0;
  } catch (const model::ModelError& e) {
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

}  // namespace dxlemu::app
