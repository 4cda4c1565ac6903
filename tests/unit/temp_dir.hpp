#pragma once

#include <stdlib.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <system_error>

namespace dxlemu::test {

/// A new directory under the system's temporary directory, removed with everything in it: for
/// the unit tests that need real files or sockets.
class TempDir {
 public:
  /// Makes TMPDIR/`prefix`-XXXXXX; fails the test when it cannot.
  explicit TempDir(const std::string& prefix = "dxlemu-test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  /// The directory.
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace dxlemu::test
