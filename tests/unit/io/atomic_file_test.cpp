#include "io/atomic_file.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "io_rig.hpp"

namespace {

using dxlemu::io::write_file_atomically;
using dxlemu::test::IoTempDir;
namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("An atomic write creates or replaces the file and leaves no temporary file",
          "[io][atomic_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "state.json";
  write_file_atomically(path, "first");
  CHECK(slurp(path) == "first");
  write_file_atomically(path, "second, longer than the first");
  CHECK(slurp(path) == "second, longer than the first");
  write_file_atomically(path, "");
  CHECK(slurp(path).empty());
  CHECK(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1);
}

TEST_CASE("The first atomic write of a path removes the temporary files of dead processes only",
          "[io][atomic_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "state.json";
  // Above any pid_max: no such process. Pid 1 lives. The others are not temporary files of ours.
  const fs::path dead = dir.path() / "state.json.tmp.999999999";
  const fs::path live = dir.path() / "state.json.tmp.1";
  const fs::path mine = dir.path() / ("state.json.tmp." + std::to_string(::getpid()));
  const fs::path not_a_pid = dir.path() / "state.json.tmp.12ab";
  const fs::path other_file = dir.path() / "other.json.tmp.999999999";
  for (const fs::path& p : {dead, live, not_a_pid, other_file}) {
    std::ofstream(p) << "left behind";
  }
  write_file_atomically(path, "saved");
  CHECK_FALSE(fs::exists(dead));
  CHECK(fs::exists(live));
  CHECK(fs::exists(not_a_pid));
  CHECK(fs::exists(other_file));
  CHECK_FALSE(fs::exists(mine));  // renamed into place
  CHECK(slurp(path) == "saved");
}

TEST_CASE("An atomic write that cannot create its file throws naming it", "[io][atomic_file]") {
  IoTempDir dir;
  const fs::path path = dir.path() / "missing" / "state.json";
  CHECK_THROWS_AS(write_file_atomically(path, "x"), std::system_error);
  CHECK_THROWS_WITH(write_file_atomically(path, "x"), Catch::Contains(path.string()));
  CHECK_FALSE(fs::exists(path));
}
