#!/usr/bin/env bash
# Installs what is missing, builds, and runs every check. CI (.ci/run) runs exactly this.
#   1. formatting of every C++ file (clang-format, the repository's .clang-format);
#   2. build/test: g++, Release (what users and packagers build), warnings as errors, MuJoCo. The
#      checks of the checkout itself (label source) and what runs in a plain build only (label
#      plain_build: the MuJoCo tests, flat resident memory, the .deb);
#   3. build/san: clang++, AddressSanitizer + UndefinedBehaviorSanitizer, libFuzzer's coverage
#      instrumentation where the fuzz targets need it, -O1, warnings as errors;
#   4. clang-tidy over our sources, each file on its own (scripts/tidy.sh);
#   5. build/san's tests: the unit tests, the command-line tests, every end-to-end suite (e2e,
#      Python package, examples, reliability) and every fuzz target's smoke run.
# Every test runs once. scripts/run.sh builds build/, which this leaves alone.
# A tool that is missing fails its step, naming the Debian package; nothing is skipped.
# Exits non-zero on the first failure and prints each step's time (docs/testing.md).
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"

steps=()
# step NAME: starts timing a step; the previous one ends.
step_name=
step_start=$SECONDS
step() {
  [ -z "$step_name" ] || steps+=("$step_name: $((SECONDS - step_start)) s")
  step_name=$1
  step_start=$SECONDS
  echo "== $1"
}

step "setup"
bash scripts/setup.sh

# Runs ctest in a build directory and adds its test count to the total printed at the end.
total=0
run_ctest() {
  local log
  log=$(mktemp)
  ctest --test-dir "$@" --output-on-failure --no-tests=error -j "$jobs" | tee "$log"
  total=$((total + $(sed -n 's/.* tests failed out of \([0-9]*\)$/\1/p' "$log" | tail -n 1)))
  rm -f "$log"
}

step "format"
bash scripts/check_format.sh

# The plain build runs the tests labelled source (they read the checkout, not the build: models,
# docs, layering) and plain_build: the MuJoCo tests (unit and e2e.physics; the sanitizer build is
# built without MuJoCo, which checks that dxlemu builds, runs and refuses physics configs without
# it, and keeps an uninstrumented library out of the sanitizer runs), the two reliability tests
# that require the daemon's resident memory to stay flat (ASan's quarantine of freed memory and
# its shadow memory make it grow by design), and those that run no dxlemu code of their own (the
# .deb, README against --help). The other unit tests are not built here: they run under the
# sanitizers.
# DXLEMU_CHECK_EXIT: a daemon that did not exit with status 0 (a crash at shutdown, a stop that
# timed out, a sanitizer report) fails the test that started it.
# Both builds are unity builds (CMAKE_UNITY_BUILD): a compiler run takes up to 8 sources of a
# target at once, so the headers they share (nlohmann-json, Catch2, Asio) are parsed and their
# templates compiled once per batch rather than once per file: a third of each build's time.
# clang-tidy checks each changed file on its own (scripts/tidy.sh), as users' plain builds
# compile it.
step "build/test: g++ Release"
configure_and_build build/test -DCMAKE_BUILD_TYPE=Release -DDXLEMU_WERROR=ON -DDXLEMU_MUJOCO=ON \
  -DDXLEMU_BUILD_UNIT_TESTS=OFF -DCMAKE_UNITY_BUILD=ON
step "build/test: tests"
DXLEMU_CHECK_EXIT=1 run_ctest build/test -L 'source|plain_build'

# One clang build serves the sanitizer suite and the fuzz smoke runs: everything is compiled with
# -fsanitize=address,undefined, what the fuzz targets link also with libFuzzer's instrumentation
# (fuzzer-no-link); the fuzz targets alone link libFuzzer's main. -O1 keeps the suite fast, line
# tables keep the reports' stacks exact; the unit tests' own sources, half of the compile time,
# build at -O0 (DXLEMU_UNIT_TEST_OPTIONS).
step "build/san: clang++ ASan + UBSan + fuzzer instrumentation"
require_tool clang++ clang "the sanitizer and fuzz build"
configure_and_build build/san -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
  "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -gline-tables-only" -DDXLEMU_UNIT_TEST_OPTIONS=-O0 \
  -DDXLEMU_SANITIZE=ON -DDXLEMU_FUZZ=ON -DDXLEMU_WERROR=ON -DDXLEMU_MUJOCO=OFF -DCMAKE_UNITY_BUILD=ON

step "clang-tidy"
bash scripts/tidy.sh build/san build/test

# Every report aborts the process that made it (a leak at exit too), so a test fails on it: the
# unit tests and the app.* checks by their exit status, and a daemon started by the end-to-end
# tests through DXLEMU_CHECK_EXIT. DXLEMU_TIMEOUT_SCALE makes the daemon's start and stop
# timeouts, and e2e.sdk_client's bound on 100 fast-timing round trips, twice as long.
step "build/san: tests and fuzz smoke runs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  DXLEMU_CHECK_EXIT=1 DXLEMU_TIMEOUT_SCALE=2 \
  run_ctest build/san -LE 'source|plain_build'
step "done"

# The unit tests' ctest tests are their files; how many test cases those ran. Catch2 exits with
# the number of names it listed, hence the || true.
cases=0
for program in build/san/tests/unit/dxlemu_unit_tests build/test/tests/unit/dxlemu_physics_tests; do
  listed=$("$program" --list-test-names-only | grep -c .) || true
  cases=$((cases + listed))
done
echo "== all tests passed"
printf '   %s\n' "${steps[@]}"
echo "$total passed, 0 failed ($cases unit test cases among them)"
