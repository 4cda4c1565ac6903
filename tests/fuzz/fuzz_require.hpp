#pragma once

#include <cstdio>
#include <cstdlib>

// A macro rather than a function so the message names the broken invariant and its line; abort()
// (not an exception) because the code under test's own exceptions must stay visible as crashes
// too, and libFuzzer saves the input of any abort.
#define FUZZ_REQUIRE(condition)                                                           \
  do {                                                                                    \
    if (!(condition)) {                                                                   \
      std::fprintf(stderr, "fuzz: invariant violated at %s:%d: %s\n", __FILE__, __LINE__, \
                   #condition);                                                           \
      std::abort();                                                                       \
    }                                                                                     \
  } while (false)

// As FUZZ_REQUIRE, with a printf-style explanation of what was seen (the failing input alone is
// often not enough to tell which packet or item broke the rule).
#define FUZZ_REQUIRE_MSG(condition, ...)                                                  \
  do {                                                                                    \
    if (!(condition)) {                                                                   \
      std::fprintf(stderr, "fuzz: invariant violated at %s:%d: %s: ", __FILE__, __LINE__, \
                   #condition);                                                           \
      std::fprintf(stderr, __VA_ARGS__);                                                  \
      std::fputc('\n', stderr);                                                           \
      std::abort();                                                                       \
    }                                                                                     \
  } while (false)

// Leaves a checker's own code out of the coverage instrumentation: its loops tell the fuzzer
// nothing about dxlemu, and their traced comparisons cost a fifth of a target's time. Code it
// calls and that is not inlined keeps its instrumentation.
#define FUZZ_NO_COVERAGE __attribute__((no_sanitize("coverage")))
