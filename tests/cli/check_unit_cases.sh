#!/usr/bin/env bash
# Test cases the unit.* tests can run, by file and by name: fails, naming the lines, when a
# TEST_CASE is outside a *_test.cpp file (tests/unit/CMakeLists.txt runs each such file's cases
# by Catch2's file tag, so a case elsewhere would never run), when a tests/unit/**/*_test.cpp is
# not named by its folder's CMakeLists.txt (never built), or its name holds ';' or '[' (CMake
# and Catch2's test specs split and parse them) or starts with '-' (the test program would take
# it for an option when run by name). Usage: check_unit_cases.sh DIR
set -uo pipefail
dir=${1:?directory}
status=0
hits=$(grep -rnE 'TEST_CASE\(("[^"]*[;[]|"-)' "$dir" --include='*.cpp' --include='*.hpp')
if [ -n "$hits" ]; then
  echo "TEST_CASE names with ';' or '[', or starting with '-' (they cannot be run by name):"
  echo "$hits"
  status=1
fi
outside=$(grep -rlE '^\s*TEST_CASE\(' "$dir" --include='*.cpp' --include='*.hpp' | grep -v '_test\.cpp$')
if [ -n "$outside" ]; then
  echo "TEST_CASEs outside a *_test.cpp file (no unit.* test would run them):"
  echo "$outside"
  status=1
fi
unlisted=$(find "$dir/unit" -name '*_test.cpp' | while read -r f; do
             grep -qw "$(basename "$f")" "$(dirname "$f")/CMakeLists.txt" 2>/dev/null || echo "$f"
           done)
if [ -n "$unlisted" ]; then
  echo "test files no CMakeLists.txt of their folder names (never built, never run):"
  echo "$unlisted"
  status=1
fi
[ "$status" -eq 0 ] && echo "test case names are ctest-safe, every case is in a listed *_test.cpp file"
exit "$status"
