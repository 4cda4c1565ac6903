// Linked into every fuzz target except fuzz_wire (which defines the same hook itself).

/// Makes UndefinedBehaviorSanitizer findings fatal in every run of the target (the fuzz build
/// compiles with recoverable checks, which would only print), so libFuzzer saves the input.
// NOLINTNEXTLINE(readability-identifier-naming,bugprone-reserved-identifier): the sanitizer's hook
extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:print_stacktrace=1";
}
