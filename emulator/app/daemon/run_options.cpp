#include "app/daemon/run_options.hpp"

#include <unistd.h>

#include <cstdlib>
#include <string>

namespace dxlemu::app {

std::filesystem::path default_control_path() {
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  const std::filesystem::path dir = runtime != nullptr && *runtime != '\0' ? runtime : "/tmp";
  return dir / ("dxlemu-" + std::to_string(::getpid()) + ".sock");
}

}  // namespace dxlemu::app
