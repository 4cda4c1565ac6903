#!/usr/bin/env bash
# Installs what dxlemu needs to build and run every check of scripts/test.sh, from Debian
# packages only (README.md, Requirements, lists the same).
# Does nothing when everything is already installed. Safe to run again.
set -euo pipefail

# Build tools and libraries. Everything here is required; nothing is downloaded at build time.
packages=(
  cmake ninja-build g++ make
  libboost-dev        # Boost.Asio (header-only), used by emulator/io only
  nlohmann-json3-dev  # models, configs, the control API
  catch2              # unit tests (Catch2 v2)
  libcli11-dev        # command line
  clang-format        # scripts/check_format.sh refuses unformatted C++
  clang-tidy          # scripts/tidy.sh: the checks of .clang-tidy
  clang               # the sanitizer and fuzz build (clang++ 14)
  libclang-rt-14-dev  # clang's sanitizer runtimes and libFuzzer
  python3             # end-to-end tests and examples (standard library only)
  python3-serial      # pyserial, for the end-to-end test that drives dxlemu as DynamixelSDK does
  python3-pytest      # the pytest fixture of python/dxlemu is tested with Debian's pytest
  python3-venv        # the test of `pip install ./python` installs into a scratch venv
  python3-setuptools  # builds python/dxlemu for pip offline (--no-build-isolation)
  python3-wheel       # setuptools' bdist_wheel, which that build needs
  tshark              # CI checks the Wireshark dissector (scripts/dxlemu.lua) on a capture
  libmujoco-dev       # physics (docs/physics.md): optional for users, built and tested by CI
  libjs-three         # the web interface's 3D view (docs/web.md), served from /usr/share/javascript
  libjs-chart.js      # the web interface's graphs
  chromium            # the web interface's browser tests (tests/web), headless
  chromium-driver     # ... driven by Selenium through chromedriver
  python3-selenium    # ... from Python
  python3-pymodbus    # Modbus RTU end-to-end tests (tests/e2e/modbus_test.py): an independent master
  python3-serial-asyncio  # ... which pymodbus's serial client imports
  mbpoll              # ... and libmodbus's command-line master
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "setup: need root or sudo to install ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive

# apt-get update only when the package lists cannot offer what is missing (fresh image, stale lists).
needs_update=0
for p in "${missing[@]}"; do
  if ! apt-cache policy "$p" 2>/dev/null | grep -q 'Candidate: [0-9]'; then
    needs_update=1
    break
  fi
done
if [ "$needs_update" -eq 1 ]; then
  "${sudo[@]}" apt-get update -q
fi
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
