#!/usr/bin/env bash
# Installs what is missing, builds, and starts the emulator: `dxlemu run` with the given
# arguments, or the default bus (three XM430-W350, IDs 1-3, 57600 baud, Protocol 2.0, linked
# at /tmp/dxlemu-dxl0) when there are none. Stop it with Ctrl-C.
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
bash scripts/setup.sh
configure_and_build build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
exec build/emulator/dxlemu run "$@"
