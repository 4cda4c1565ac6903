#!/usr/bin/env bash
# Runs clang-tidy (the repository's .clang-tidy) over our C++ sources. Every finding is an error:
# prints the findings and exits 1. A missing clang-tidy, or a file it cannot parse, fails too.
#
# Each file is checked on its own, with the command a plain clang++ build compiles it with: the
# compile database of build/tidy, which this script configures and never builds (clang++, every
# target, MuJoCo, no unity batches, no precompiled headers). So a file that does not include what
# it uses fails here even where scripts/test.sh's unity builds compile it in a batch with others.
#
# A full run takes about 12 CPU-minutes (the checks walk every header a file includes), so by
# default only the files that can have changed since the commit in scripts/tidy-clean-commit are
# checked: that commit passed a full run, and a source file is checked again when it, or any file
# its object was compiled from (ninja's dependency logs of the BUILD_DIRs, default build/san and
# build/test, those of scripts/test.sh), differs from that commit, committed or not. A unity
# batch's object counts for every source it includes. Everything is checked when .clang-tidy or
# this script changed, when that commit is not in the history (a shallow clone, rewritten
# history), or when there is no build with a ninja dependency log.
#
# Usage: scripts/tidy.sh [--full] [BUILD_DIR...]
#   --full  check every file; when everything is clean and committed, write HEAD to
#           scripts/tidy-clean-commit (commit that file so that later runs start from there)
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"

full=0
if [ "${1:-}" = --full ]; then
  full=1
  shift
fi
builds=("$@")
if [ ${#builds[@]} -eq 0 ]; then
  for dir in build/san build/test; do
    [ -d "$dir" ] && builds+=("$dir")
  done
fi
record=scripts/tidy-clean-commit
require_tool clang-tidy clang-tidy "scripts/tidy.sh"
require_tool clang++ clang "scripts/tidy.sh (its compile database is clang++'s)"

database=build/tidy
cmake -S "$repo_root" -B "$database" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_UNITY_BUILD=OFF -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON -DDXLEMU_MUJOCO=ON \
  -DDXLEMU_BUILD_UNIT_TESTS=ON -DDXLEMU_BUILD_BENCH=ON -DDXLEMU_FUZZ=OFF >/dev/null
mapfile -t all < <(find emulator tests/unit tests/support bench -type f -name '*.cpp' | sort)
# A source no target compiles has no command: say so rather than let clang-tidy guess one.
unbuilt=$(printf '%s\n' "${all[@]}" | while read -r f; do
            grep -qF "\"file\": \"$repo_root/$f\"" "$database/compile_commands.json" || echo "$f"
          done)
if [ -n "$unbuilt" ]; then
  echo "clang-tidy: no target compiles these files (add them to a CMakeLists.txt):" >&2
  echo "$unbuilt" >&2
  exit 1
fi

# why_full: prints why every file must be checked, or nothing when the changed ones suffice.
why_full() {
  [ "$full" -eq 0 ] || { echo "--full"; return; }
  local base
  base=$(grep -v '^#' "$record" 2>/dev/null | head -n 1 || true)
  [ -n "$base" ] || { echo "no commit in $record"; return; }
  git cat-file -e "$base^{commit}" 2>/dev/null || { echo "$base (in $record) is not in the history"; return; }
  [ ${#builds[@]} -gt 0 ] || { echo "no build directory: no dependency log"; return; }
  local build
  for build in "${builds[@]}"; do
    [ -f "$build/build.ninja" ] || { echo "$build was not built with ninja: no dependency log"; return; }
  done
  if ! git diff --quiet "$base" -- .clang-tidy scripts/tidy.sh; then
    echo ".clang-tidy or scripts/tidy.sh changed since $base"
  fi
}
reason=$(why_full)

if [ -n "$reason" ]; then
  files=("${all[@]}")
  scope="all ${#all[@]} files ($reason)"
else
  base=$(grep -v '^#' "$record" | head -n 1)
  # Paths changed since the clean commit, in the work tree too, and new files; absolute, as ninja
  # writes them.
  changed=$( { git diff --name-only "$base" --; git ls-files --others --exclude-standard; } |
             sed "s|^|$repo_root/|" | sort -u)
  # A source file whose object depends on a changed path. ninja -t deps prints each object
  # ("DIR/x.cpp.o: #deps ..."), then every file it read, one per indented line: the source (the
  # one of ours named x.cpp; not always the first, a sanitizer's ignore list comes before it) and
  # every header; a unity batch (DIR/Unity/unity_N_cxx.cxx.o) reads each of its sources. A source
  # the logs do not know (never built) is checked whenever it changed.
  mapfile -t files < <(for build in "${builds[@]}"; do ninja -C "$build" -t deps 2>/dev/null; done |
                       awk -v changed="$changed" \
      -v ours="$(printf '%s\n' "${all[@]}")" -v root="$repo_root/" '
    function flush(   i) {
      for (i = 1; i <= count; ++i) {
        known[sources[i]] = 1
        if (read_changed) dirty[sources[i]] = 1
      }
    }
    BEGIN {
      n = split(changed, c, "\n"); for (i = 1; i <= n; ++i) hit[c[i]] = 1
      n = split(ours, f, "\n"); for (i = 1; i <= n; ++i) mine[root f[i]] = 1
    }
    /^[^ ]/ {
      flush()
      object = $1
      sub(/:$/, "", object)
      k = split(object, parts, "/")
      name = "/" parts[k]
      sub(/\.o$/, "", name)
      unity = name ~ /^\/unity_[0-9]+_cxx\.cxx$/
      count = 0
      read_changed = 0
      next
    }
    /^    / {
      path = substr($0, 5)
      if (path in hit) read_changed = 1
      if (!(path in mine)) next
      if (unity || (count == 0 && substr(path, length(path) - length(name) + 1) == name))
        sources[++count] = path
    }
    END {
      flush()
      n = split(ours, f, "\n")
      for (i = 1; i <= n; ++i) {
        p = root f[i]
        if ((p in dirty) || ((p in hit) && !(p in known))) print f[i]
      }
    }')
  scope="${#files[@]} of ${#all[@]} files (those that include a change since $base, the last full clean run)"
fi

echo "clang-tidy: checking $scope"
if [ ${#files[@]} -gt 0 ]; then
  # One clang-tidy per file, as many at once as there are cores. xargs exits non-zero when any
  # of them did: a finding (--warnings-as-errors) or a file that does not compile.
  log=$(mktemp)
  trap 'rm -f "$log"' EXIT
  status=0
  printf '%s\0' "${files[@]}" |
    xargs -0 -n 1 -P "$jobs" clang-tidy -p "$database" --quiet --warnings-as-errors='*' >"$log" 2>&1 ||
    status=$?
  if [ "$status" -ne 0 ]; then
    grep -vE '^[0-9]+ warnings? (and [0-9]+ errors? )?generated\.$' "$log" || true
    echo "clang-tidy: findings or errors above (exit status $status)" >&2
    exit 1
  fi
fi
echo "clang-tidy: ${#files[@]} files clean"

if [ "$full" -eq 1 ]; then
  if [ -z "$(git status --porcelain)" ]; then
    { echo "# A commit at which scripts/tidy.sh --full found nothing: scripts/tidy.sh checks what changed since."
      git rev-parse HEAD; } >"$record"
    echo "clang-tidy: wrote $(git rev-parse --short HEAD) to $record: commit it"
  else
    echo "clang-tidy: $record not updated: the work tree has uncommitted changes"
  fi
fi
