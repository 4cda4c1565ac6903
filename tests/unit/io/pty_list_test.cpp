// DXLEMU_PTYS as the preload library reads it (docs/exec.md "Using the library by hand").
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "io/preload/pty_list.hpp"

using namespace dxlemu::preload;

namespace {

std::vector<std::string> paths(const PtyList& list) {
  return {list.paths, list.paths + list.count};
}

}  // namespace

TEST_CASE("DXLEMU_PTYS is split at colons, empty entries skipped", "[preload]") {
  static PtyList list;
  CHECK(parse_pty_list("/dev/pts/3:/tmp/dxlemu-dxl0", list) == PtyListError::None);
  CHECK(paths(list) == std::vector<std::string>{"/dev/pts/3", "/tmp/dxlemu-dxl0"});
  CHECK(parse_pty_list(":/dev/pts/3::/tmp/a:", list) == PtyListError::None);
  CHECK(paths(list) == std::vector<std::string>{"/dev/pts/3", "/tmp/a"});
}

TEST_CASE("An unset or empty DXLEMU_PTYS names no path and is no error", "[preload]") {
  static PtyList list;
  CHECK(parse_pty_list(nullptr, list) == PtyListError::None);
  CHECK(list.count == 0);
  CHECK(parse_pty_list("", list) == PtyListError::None);
  CHECK(list.count == 0);
}

TEST_CASE("A DXLEMU_PTYS that cannot be read whole names no path at all", "[preload]") {
  static PtyList list;
  CHECK(parse_pty_list("/dev/pts/3:dxl0", list) == PtyListError::NotAbsolute);
  CHECK(list.count == 0);
  std::string many;
  for (std::size_t i = 0; i <= kMaxPtyPaths; ++i) {
    many += "/dev/pts/" + std::to_string(i) + ":";
  }
  CHECK(parse_pty_list(many.c_str(), list) == PtyListError::TooMany);
  CHECK(list.count == 0);
  const std::string long_path = "/" + std::string(kMaxPtyListBytes, 'a');
  CHECK(parse_pty_list(long_path.c_str(), list) == PtyListError::TooLong);
  CHECK(list.count == 0);
  CHECK(std::string(pty_list_error_text(PtyListError::TooMany)) ==
        "DXLEMU_PTYS names more than 64 paths");
}
