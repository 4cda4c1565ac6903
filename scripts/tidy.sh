#!/usr/bin/env bash
# Runs clang-tidy (the repository's .clang-tidy) over our C++ sources with the compile databases of
# build directories (default build/, configured and built if it has none). Every finding is an
# error: prints the findings and exits 1. A missing clang-tidy, or a file it cannot parse, fails too.
# With several directories (scripts/test.sh: build/san, whose clang commands serve clang-tidy best,
# then build/test for what only it builds: MuJoCo), each file is checked with the command of the
# first directory that compiles it. Precompiled headers are left out of the commands: a file is
# checked with the includes it names, and clang cannot read g++'s precompiled headers.
#
# A full run takes about 12 CPU-minutes (the checks walk every header a file includes), so by
# default only the files that can have changed since the commit in scripts/tidy-clean-commit are
# checked: that commit passed a full run, and a source file is checked again when it, or any
# header it includes (ninja's dependency logs of the builds), differs from that commit, committed
# or not. Everything is checked when .clang-tidy or this script changed, when that commit is not
# in the history (a shallow clone, rewritten history), or when a build has no ninja dependency log.
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
[ ${#builds[@]} -gt 0 ] || builds=(build)
record=scripts/tidy-clean-commit
require_tool clang-tidy clang-tidy "scripts/tidy.sh"
require_tool python3 python3 "scripts/tidy.sh (it merges the compile databases)"
if [ ! -f "${builds[0]}/compile_commands.json" ]; then
  configure_and_build "${builds[0]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
mapfile -t all < <(find emulator tests/unit tests/support bench -type f -name '*.cpp' | sort)

# One compile database of every directory's commands, the first directory's where several
# compile a file, without the precompiled-header options.
database=$(mktemp -d)
trap 'rm -rf "$database"' EXIT
python3 - "$database/compile_commands.json" "${builds[@]}" <<'PYTHON'
import json, re, shlex, sys
out, builds = sys.argv[1], sys.argv[2:]
merged = {}
for build in builds:
    try:
        entries = json.load(open(f"{build}/compile_commands.json"))
    except FileNotFoundError:
        sys.exit(f"tidy.sh: {build} has no compile_commands.json: configure it first")
    for entry in entries:
        if entry["file"] in merged:
            continue
        words = shlex.split(entry.pop("command")) if "command" in entry else entry.pop("arguments")
        kept = []
        skip = 0
        for i, word in enumerate(words):
            if skip:
                skip -= 1
                continue
            # g++: -include .../cmake_pch.hxx; clang: -Xclang -include-pch -Xclang FILE.pch and
            # -Xclang -include -Xclang .../cmake_pch.hxx.
            if word == "-include" and words[i + 1].endswith("cmake_pch.hxx"):
                skip = 1
            elif word == "-Xclang" and words[i + 1] in ("-include-pch", "-include") and \
                    re.search(r"cmake_pch\.hxx(\.pch)?$", words[i + 3]):
                skip = 3
            elif word == "-Winvalid-pch":
                pass
            else:
                kept.append(word)
        entry["arguments"] = kept
        merged[entry["file"]] = entry
json.dump(list(merged.values()), open(out, "w"), indent=1)
PYTHON

# why_full: prints why every file must be checked, or nothing when the changed ones suffice.
why_full() {
  [ "$full" -eq 0 ] || { echo "--full"; return; }
  local base
  base=$(grep -v '^#' "$record" 2>/dev/null | head -n 1 || true)
  [ -n "$base" ] || { echo "no commit in $record"; return; }
  git cat-file -e "$base^{commit}" 2>/dev/null || { echo "$base (in $record) is not in the history"; return; }
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
  # every header. A source the logs do not know (never built) is checked whenever it changed.
  mapfile -t files < <(for build in "${builds[@]}"; do ninja -C "$build" -t deps 2>/dev/null; done |
                       awk -v changed="$changed" \
      -v ours="$(printf '%s\n' "${all[@]}")" -v root="$repo_root/" '
    function flush() {
      if (source == "") return
      known[source] = 1
      if (read_changed) dirty[source] = 1
    }
    BEGIN { n = split(changed, c, "\n"); for (i = 1; i <= n; ++i) hit[c[i]] = 1 }
    /^[^ ]/ {
      flush()
      object = $1
      sub(/:$/, "", object)
      k = split(object, parts, "/")
      name = "/" parts[k]
      sub(/\.o$/, "", name)
      source = ""
      read_changed = 0
      next
    }
    /^    / {
      path = substr($0, 5)
      if (path in hit) read_changed = 1
      if (source == "" && index(path, root) == 1 &&
          substr(path, length(path) - length(name) + 1) == name) source = path
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
  log=$database/log
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
