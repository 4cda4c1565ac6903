#include "support/flags.hpp"

#include <stdexcept>
#include <vector>

namespace dxlemu::bench {

void parse_flags(int argc, char** argv, const FlagHandlers& handlers, const std::string& usage) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() % 2 != 0) {
    throw std::invalid_argument(usage);
  }
  try {
    for (std::size_t i = 0; i < args.size(); i += 2) {
      const auto handler = handlers.find(args[i]);
      if (handler == handlers.end()) {
        throw std::invalid_argument(args[i]);
      }
      handler->second(args[i + 1]);
    }
  } catch (const std::logic_error&) {  // an unknown flag, or stoi/stod refusing a number
    throw std::invalid_argument(usage);
  }
}

}  // namespace dxlemu::bench
