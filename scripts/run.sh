#!/usr/bin/env bash
# Installs what is missing, builds, and starts the emulator: `dxlemu run` with the given
# arguments, or, when there are none, the default bus (three XM430-W350, IDs 1-3, 57600 baud,
# Protocol 2.0, linked at /tmp/dxlemu-dxl0) with its web interface on 127.0.0.1:8080: the URL to
# open, with its access token, is printed (docs/web.md). Stop it with Ctrl-C.
# Builds build/ (Release), and in it only what the emulator runs: the dxlemu executable and the
# preload library of `dxlemu exec`. scripts/test.sh builds in build/test and build/san, so
# neither rebuilds the other's tree.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
bash scripts/setup.sh
cmake -S "$repo_root" -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DDXLEMU_WERROR=OFF >/dev/null
cmake --build build -j "$jobs" --target dxlemu dxlemu_preload
if [ $# -eq 0 ]; then
  set -- --web 8080
fi
exec build/emulator/dxlemu run "$@"
