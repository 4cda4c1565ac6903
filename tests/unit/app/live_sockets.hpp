#pragma once

#include <filesystem>
#include <vector>

#include "app/cli/ctl_request.hpp"

namespace dxlemu::test {

/// A LiveSocketFinder that finds the sockets `live`, whatever directory it is asked about.
inline app::LiveSocketFinder finding(const std::vector<std::filesystem::path>& live) {
  return [live](const std::filesystem::path&) { return live; };
}

}  // namespace dxlemu::test
