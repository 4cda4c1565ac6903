#include "app/config/trajectory_library.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <system_error>

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 2> kExtensions = {".csv", ".jsonl"};

}  // namespace

fs::path find_trajectory(const std::string& argument, const std::vector<fs::path>& dirs) {
  std::error_code error;
  if (fs::is_regular_file(argument, error)) {
    return argument;
  }
  std::vector<std::string> known;
  for (const fs::path& dir : dirs) {
    if (argument.find('/') == std::string::npos) {
      for (const char* extension : kExtensions) {
        fs::path candidate = dir / (argument + extension);
        if (fs::is_regular_file(candidate, error)) {
          return candidate;
        }
      }
    }
    if (fs::is_directory(dir, error)) {
      for (const auto& entry : fs::directory_iterator(dir, error)) {
        const fs::path& path = entry.path();
        if (std::find(kExtensions.begin(), kExtensions.end(), path.extension()) !=
            kExtensions.end()) {
          known.push_back(path.stem().string());
        }
      }
    }
  }
  std::sort(known.begin(), known.end());
  std::string names;
  for (const std::string& name : known) {
    names += (names.empty() ? "" : ", ") + name;
  }
  throw std::invalid_argument(argument + " is no file, nor a shipped trajectory (known: " +
                              (names.empty() ? "none" : names) + "; docs/hands.md)");
}

}  // namespace dxlemu::app
