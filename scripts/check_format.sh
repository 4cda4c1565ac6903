#!/usr/bin/env bash
# Fails, naming the files, when a C++ file is not formatted with the repository's .clang-format.
# Fix with: clang-format -i FILE...
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
require_tool clang-format clang-format "scripts/check_format.sh"
mapfile -t files < <(find emulator tests bench -type f \( -name '*.cpp' -o -name '*.hpp' \) 2>/dev/null | sort)
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "Not formatted (run: clang-format -i ${bad[*]}):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "format: ${#files[@]} C++ files clean"
