#!/usr/bin/env bash
# Installs what is missing, builds, and starts the emulator. Arguments go to `dxlemu`.
# (Until the daemon lands, dxlemu prints its version and exits.)
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"
bash scripts/setup.sh
configure_and_build build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
exec build/dxlemu "$@"
