// run_child with real commands of the base system (sh).
#include "io/child_process.hpp"

#include <catch2/catch.hpp>

#include <csignal>
#include <map>
#include <string>
#include <vector>

namespace {

using dxlemu::io::kExitNotFound;
using dxlemu::io::kExitSignalBase;
using dxlemu::io::run_child;

int sh(const std::string& script, const std::map<std::string, std::string>& environment = {}) {
  return run_child({"sh", "-c", script}, environment);
}

}  // namespace

TEST_CASE("A child's exit status is returned, or 128 plus the signal that killed it",
          "[io][child_process]") {
  CHECK(sh("exit 0") == 0);
  CHECK(sh("exit 3") == 3);
  CHECK(sh("kill -KILL $$") == kExitSignalBase + SIGKILL);
}

TEST_CASE("A command that is not found gives 127", "[io][child_process]") {
  CHECK(run_child({"dxlemu-no-such-command-anywhere"}, {}) == kExitNotFound);
}

TEST_CASE("The child gets this process's environment with the changes", "[io][child_process]") {
  ::setenv("DXLEMU_TEST_KEPT", "kept", 1);
  ::setenv("DXLEMU_TEST_CHANGED", "old", 1);
  CHECK(sh(R"(test "$DXLEMU_TEST_KEPT" = kept && test "$DXLEMU_TEST_CHANGED" = new &&)"
           R"( test "$DXLEMU_TEST_ADDED" = added)",
           {{"DXLEMU_TEST_CHANGED", "new"}, {"DXLEMU_TEST_ADDED", "added"}}) == 0);
  ::unsetenv("DXLEMU_TEST_KEPT");
  ::unsetenv("DXLEMU_TEST_CHANGED");
}

TEST_CASE("A SIGTERM sent to this process while the child runs is passed on to the child",
          "[io][child_process]") {
  // The child signals its parent (this test), which passes the signal back: the child dies of
  // it. Without the passing on the child would run its minute out and exit 0.
  CHECK(sh("kill -TERM $PPID; exec sleep 60") == kExitSignalBase + SIGTERM);
}
