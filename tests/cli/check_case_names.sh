#!/usr/bin/env bash
# catch_discover_tests splits a Catch2 test name at ';' and CMake list handling mangles '['; a
# name that starts with '-' reaches the test binary as an option: fails, naming the lines, when
# a TEST_CASE name does any of that. Usage: check_case_names.sh DIR
set -uo pipefail
hits=$(grep -rnE 'TEST_CASE\(("[^"]*[;[]|"-)' "${1:?directory}" --include='*.cpp')
if [ -n "$hits" ]; then
  echo "TEST_CASE names with ';' or '[', or starting with '-' (ctest cannot run them one by one):"
  echo "$hits"
  exit 1
fi
echo "test case names are ctest-safe"
