#!/usr/bin/env bash
# Fails, naming the files, when a C++ file is not formatted with the repository's .clang-format.
# Fix with: clang-format -i FILE...
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
require_tool clang-format clang-format "scripts/check_format.sh"
mapfile -t files < <(find emulator tests bench -type f \( -name '*.cpp' -o -name '*.hpp' \) 2>/dev/null | sort)
# One clang-format for all files (a process per file spent ten times as long starting up); each
# violation is reported as FILE:LINE:COLUMN: error: code should be clang-formatted.
status=0
report=$(clang-format --dry-run -Werror "${files[@]}" 2>&1 >/dev/null) || status=$?
mapfile -t bad < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' <<<"$report" |
                   sort -u)
if [ "$status" -ne 0 ] && [ ${#bad[@]} -eq 0 ]; then
  echo "clang-format failed (exit status $status):"
  echo "$report"
  exit 1
fi
if [ ${#bad[@]} -gt 0 ]; then
  echo "Not formatted (run: clang-format -i ${bad[*]}):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "format: ${#files[@]} C++ files clean"
