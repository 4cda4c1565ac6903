#!/usr/bin/env bash
# Runs the end-to-end tests (e2e.*, python.package, examples.*) with every dxlemu they start
# under valgrind's memcheck, and fails on any memcheck error: an invalid read or write, a use of
# uninitialised memory, a bad free, or memory definitely, indirectly or possibly lost at exit.
# The tests start dxlemu through tests/e2e/dxl_client.py and python/dxlemu/daemon.py, which run
# it under $DXLEMU_WRAPPER; with $DXLEMU_CHECK_EXIT=1 a daemon that does not exit with status 0
# (valgrind's --error-exitcode) fails the test that started it. Every dxlemu run is clean without
# any suppression; should a false positive in a system library ever need one, put it in
# scripts/memcheck.supp with the reason and pass --suppressions below.
#
# Builds its own tree, build-memcheck/ (RelWithDebInfo, as users get it). Not run by CI: the
# tests take about 4 minutes on 2 cores (under valgrind, `dxlemu models` takes 2.7 s instead
# of 0.05), the build as long again. Run it by hand after a change to memory handling, and
# before a release.
#
# e2e.sdk_client is left out: what it checks is that replies come within DynamixelSDK's own
# timeouts (a few ms per byte), which a daemon under valgrind cannot meet; the code it runs is
# the code e2e.daemon runs.
#
# Usage: scripts/memcheck.sh [CTEST_REGEX]   (default: ^(e2e|python|examples)\.)
# Each valgrind log is kept in build-memcheck/memcheck/dxlemu.PID.log; those with an error are
# printed at the end.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"

tests=${1:-'^(e2e|python|examples)\.'}

bash scripts/setup.sh
if ! command -v valgrind >/dev/null 2>&1; then
  echo "memcheck: installing valgrind" >&2
  sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -q --no-install-recommends valgrind
fi

echo "== build (build-memcheck/)"
configure_and_build build-memcheck -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDXLEMU_BUILD_BENCH=OFF

logs=$repo_root/build-memcheck/memcheck
rm -rf "$logs"
mkdir -p "$logs"

# Leaks count as errors (exit status 99); memory still reachable at exit does not (there is none
# today).
export DXLEMU_WRAPPER="valgrind --tool=memcheck --error-exitcode=99 --leak-check=full \
--show-leak-kinds=definite,indirect,possible --errors-for-leak-kinds=definite,indirect,possible \
--num-callers=40 --log-file=$(printf %q "$logs")/dxlemu.%p.log"
export DXLEMU_CHECK_EXIT=1
export DXLEMU_TIMEOUT_SCALE=10

echo "== tests matching $tests, dxlemu under valgrind"
status=0
ctest --test-dir build-memcheck -R "$tests" -E '^e2e\.sdk_client$' --output-on-failure -j "$jobs" ||
  status=$?

# Every log ends with the process's ERROR SUMMARY and, when it exited normally, a LEAK SUMMARY.
runs=0
failed=()
errors=0
definitely=0
indirectly=0
for log in "$logs"/dxlemu.*.log; do
  [ -e "$log" ] || continue
  runs=$((runs + 1))
  count=$(sed -n 's/.*ERROR SUMMARY: \([0-9,]*\) errors.*/\1/p' "$log" | tr -d , | tail -n 1)
  if [ -z "$count" ]; then
    # Killed before it could summarise (a test's SIGKILL): nothing to check.
    continue
  fi
  errors=$((errors + count))
  [ "$count" -eq 0 ] || failed+=("$log")
  lost=$(sed -n 's/.*definitely lost: \([0-9,]*\) bytes.*/\1/p' "$log" | tr -d , | tail -n 1)
  definitely=$((definitely + ${lost:-0}))
  lost=$(sed -n 's/.*indirectly lost: \([0-9,]*\) bytes.*/\1/p' "$log" | tr -d , | tail -n 1)
  indirectly=$((indirectly + ${lost:-0}))
done
for log in "${failed[@]}"; do
  echo "== $log"
  cat "$log"
done
echo "== memcheck: $runs dxlemu runs, $errors errors, $definitely bytes definitely lost," \
  "$indirectly bytes indirectly lost (logs in $logs)"
if [ "$status" -ne 0 ] || [ "$errors" -ne 0 ]; then
  echo "== memcheck failed" >&2
  exit 1
fi
echo "== memcheck clean"
