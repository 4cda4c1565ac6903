# Shared by the scripts in this folder: the repository root, the generator and the job count.
# Sourced, not run.
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
else
  generator=()
fi
jobs=$(nproc 2>/dev/null || echo 2)

# configure_and_build DIR [cmake options...]: configures DIR once, then builds it.
configure_and_build() {
  local dir=$1
  shift
  cmake -S "$repo_root" -B "$dir" "${generator[@]}" "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
}

# require_tool COMMAND PACKAGE WHAT: fails, naming the Debian package, when COMMAND is missing.
# scripts/setup.sh installs every package the checks use; this catches a machine it did not set up.
require_tool() {
  command -v "$1" >/dev/null 2>&1 && return 0
  echo "error: $1 not found: $3 needs it (Debian package $2; scripts/setup.sh installs it)" >&2
  exit 1
}
