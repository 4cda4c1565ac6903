// dxlemu: a DYNAMIXEL servo-bus emulator. Until the daemon exists (issue 5) the program only
// reports its version and what it is.
#include <CLI/CLI.hpp>
#include <iostream>

#include "dxlemu/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"dxlemu: emulates a chain of ROBOTIS DYNAMIXEL servos on a pseudo-terminal"};
  app.set_version_flag("--version", std::string("dxlemu ") + dxlemu::kVersion);
  CLI11_PARSE(app, argc, argv);
  std::cout << "dxlemu " << dxlemu::kVersion
            << ": the emulator daemon is not built yet; see README.md for what exists.\n";
  return 0;
}
