#!/usr/bin/env bash
# DESIGN.md: core code (sim, wire, model, physics, bus, faults) and the control API's commands (control)
# never include Asio and never read the wall clock or sleep. Time comes from the Scheduler or as
# an argument. Exits 1 naming each offending line.
set -uo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
core_dirs=()
for d in sim wire model physics bus faults control; do
  [ -d "$root/emulator/$d" ] && core_dirs+=("$root/emulator/$d")
done
pattern='boost/asio|#include <asio|steady_clock|system_clock|high_resolution_clock|clock_gettime|gettimeofday|std::time\(|[^_a-z]time\(nullptr|sleep_for|sleep_until|usleep|nanosleep|[^_a-z]sleep\('
hits=$(grep -rnE "$pattern" "${core_dirs[@]}" --include='*.hpp' --include='*.cpp' || true)
if [ -n "$hits" ]; then
  echo "Asio or a clock read in core code (see ../shared/DESIGN.md, Layers and Time):"
  echo "$hits"
  exit 1
fi
# The bus asks faults/ through bus::FaultHooks: faults/ depends on bus/, never the reverse.
hits=$(grep -rn '#include "faults/' "$root/emulator/bus" --include='*.hpp' --include='*.cpp' || true)
if [ -n "$hits" ]; then
  echo "bus/ includes faults/ (the bus asks bus::FaultHooks, which faults/ implements):"
  echo "$hits"
  exit 1
fi
echo "core layers clean: ${core_dirs[*]#$root/}"
