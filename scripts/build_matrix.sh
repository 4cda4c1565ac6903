#!/usr/bin/env bash
# Builds everything (emulator, tests, benches) in every CMake build type with both compilers,
# warnings as errors: what a packager or a user with either compiler may build. Each build goes
# to build/matrix/COMPILER-TYPE. Not run by CI, which builds g++ Release and a clang sanitizer
# build (scripts/test.sh); run it after a change that may warn only at some optimisation level
# or with one compiler, and before a release. About 25 minutes on 2 cores.
# Usage: scripts/build_matrix.sh [BUILD_TYPE...]   (default: Debug Release RelWithDebInfo MinSizeRel)
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
bash scripts/setup.sh

types=("$@")
[ ${#types[@]} -gt 0 ] || types=(Debug Release RelWithDebInfo MinSizeRel)
results=()
for cxx in g++ clang++; do
  require_tool "$cxx" "$([ "$cxx" = g++ ] && echo g++ || echo clang)" "scripts/build_matrix.sh"
  for type in "${types[@]}"; do
    dir=build/matrix/$cxx-$type
    echo "== $cxx $type ($dir)"
    start=$SECONDS
    configure_and_build "$dir" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="$type" -DDXLEMU_WERROR=ON
    results+=("$cxx $type: built without warnings in $((SECONDS - start)) s")
  done
done
echo "== every build type built warning-free"
printf '   %s\n' "${results[@]}"
