#!/usr/bin/env bash
# Runs clang-tidy (the repository's .clang-tidy) over our C++ sources, using build/'s
# compile_commands.json. Prints nothing but the summary when clean; exits 1 on a finding.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
[ -f build/compile_commands.json ] || configure_and_build build -DCMAKE_BUILD_TYPE=RelWithDebInfo
mapfile -t files < <(find emulator tests/unit tests/support bench -type f -name '*.cpp' | sort)
# One clang-tidy per file, as many at once as there are cores.
out=$(printf '%s\0' "${files[@]}" |
  xargs -0 -n 1 -P "$jobs" clang-tidy -p build --quiet 2>/dev/null | grep -E '(warning|error):' || true)
if [ -n "$out" ]; then
  echo "$out"
  exit 1
fi
echo "clang-tidy: ${#files[@]} files clean"
