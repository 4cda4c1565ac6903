#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test:
#   1. formatting of all C++ files (clang-format, the repository's .clang-format);
#   2. the unit tests, the layering check and the app smoke test (build/, ctest), then clang-tidy;
#   3. the same tests, the end-to-end ones included, with the unit tests and the dxlemu daemon
#      built with AddressSanitizer + UndefinedBehaviorSanitizer (build/asan);
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

# DXLEMU_CHECK_EXIT: a daemon that did not exit with status 0 (a crash at shutdown, a stop that
# timed out) fails the test that started it, here as under ASan below.
echo "== build and unit tests (build/)"
configure_and_build build -DCMAKE_BUILD_TYPE=RelWithDebInfo
DXLEMU_CHECK_EXIT=1 run_ctest build
bash scripts/tidy.sh

# Every report aborts the process that made it (a leak at exit too), so a test fails on it: the
# unit tests and the app.* checks by their exit status, and a daemon started by the end-to-end
# tests, the Python package's tests and the examples through DXLEMU_CHECK_EXIT
# (python/dxlemu/daemon.py), which fails the test whose daemon did not exit with status 0.
# Benches are not built (the build above compiles them). Left out: app.cpack_makes_a_deb, which
# runs no dxlemu code (it packs the binary, 10 s under ASan), and the two reliability tests that
# require the daemon's resident memory to stay flat, which ASan's quarantine of freed memory
# (up to 256 MiB) and its shadow memory make grow by design. The Debug build under ASan is slow
# (1 to 2 s to load the model library): DXLEMU_TIMEOUT_SCALE makes the daemon's start and stop
# timeouts, and e2e.sdk_client's bound on 100 fast-timing round trips, twice as long.
echo "== all tests under ASan + UBSan (build/asan)"
configure_and_build build/asan -DCMAKE_BUILD_TYPE=Debug -DDXLEMU_SANITIZE=ON -DDXLEMU_BUILD_APP=ON \
  -DDXLEMU_BUILD_BENCH=OFF
not_under_asan='^(app\.cpack_makes_a_deb|reliability\.(garbage_soak|unread_replies_do_not_pile_up))$'
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  DXLEMU_CHECK_EXIT=1 DXLEMU_TIMEOUT_SCALE=2 \
  run_ctest build/asan -E "$not_under_asan"

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
