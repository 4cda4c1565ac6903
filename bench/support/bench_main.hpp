#pragma once

#include <exception>
#include <iostream>

#include "serial_port.hpp"

namespace dxlemu::bench {

/// A bench's main(): parses its options with `parse`, pins the bench (and every process it
/// starts, which inherits it) to `options.cpu` when that is set (>= 0), and runs `body(options)`.
/// An exception ends the bench with "NAME: reason" on stderr and exit status 1.
template <class Options, class Body>
int bench_main(const char* name, int argc, char** argv, Options (*parse)(int, char**), Body body) {
  try {
    const Options options = parse(argc, argv);
    if (options.cpu >= 0) {
      pin_to_cpu(options.cpu);  // before starting anything
    }
    body(options);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << name << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dxlemu::bench
