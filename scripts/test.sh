#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test:
#   1. formatting of all C++ files (clang-format, the repository's .clang-format);
#   2. the unit tests, the layering check and the app smoke test (build/, ctest), then clang-tidy;
#   3. the same unit tests built with AddressSanitizer + UndefinedBehaviorSanitizer (build/asan);
#   4. when clang++ is present, the libFuzzer smoke runs (build/fuzz).
# Exits non-zero on the first failure. CI (.ci/run) runs exactly this.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"

bash scripts/setup.sh
bash scripts/check_format.sh

# Runs ctest in a build directory and adds its test count to the total printed at the end.
total=0
run_ctest() {
  local log
  log=$(mktemp)
  ctest --test-dir "$@" --output-on-failure -j "$jobs" | tee "$log"
  total=$((total + $(sed -n 's/.* tests failed out of \([0-9]*\)$/\1/p' "$log" | tail -n 1)))
  rm -f "$log"
}

echo "== build and unit tests (build/)"
configure_and_build build -DCMAKE_BUILD_TYPE=RelWithDebInfo
run_ctest build
bash scripts/tidy.sh

echo "== unit tests under ASan + UBSan (build/asan)"
configure_and_build build/asan -DCMAKE_BUILD_TYPE=Debug -DDXLEMU_SANITIZE=ON -DDXLEMU_BUILD_APP=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  run_ctest build/asan

if command -v clang++ >/dev/null 2>&1; then
  echo "== fuzz smoke runs (build/fuzz, clang++)"
  configure_and_build build/fuzz -DCMAKE_CXX_COMPILER=clang++ -DDXLEMU_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
  run_ctest build/fuzz
else
  echo "== fuzz smoke runs skipped: clang++ not installed (apt-get install clang libclang-rt-14-dev)"
fi
echo "== all tests passed"
echo "$total passed, 0 failed"
