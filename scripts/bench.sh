#!/usr/bin/env bash
# Builds the benchmarks of bench/ with the emulator, runs them, and writes their figures into
# docs/benchmarks.md between the "bench.sh: begin/end" markers (the rest of the page is written
# by hand). Benchmarks are not tests: nothing here passes or fails on a figure, and CI never runs
# this. Run it on an idle machine; with the defaults it takes under ten minutes on a fresh clone
# (the build included). The benches: reply_latency (timing fidelity), throughput (against a bare
# PTY program, and the cost of the trace, the capture and the control API), scale (253 servos on
# one bus, 32 ports in one process).
#
# Each run measures twice: with the bench and dxlemu free to run on any CPU (what a user gets),
# and with both pinned to one CPU (reply_latency --cpu N), which takes the cost of waking an idle
# CPU out of the figures and so shows the driver's own precision.
#
# Usage: scripts/bench.sh [--runs R] [--count N] [--rounds T] [--seconds S]
#   --runs R     reply_latency: how many times to run each measurement (default 2): the figures
#                of one run say little on a shared machine
#   --count N    reply_latency: round trips per instruction and baud rate (default 400)
#   --rounds T   throughput: rounds, each measuring every target once (default 5); a ratio is
#                taken within a round and the median of the rounds reported, as the other
#                tenants of a shared machine change the figures from one second to the next
#   --seconds S  throughput and scale: seconds per measurement (default 2)
set -euo pipefail
source "$(dirname "$0")/common.sh"
cd "$repo_root"

runs=2
count=400
rounds=5
seconds=2
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --count) count=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    *) echo "usage: scripts/bench.sh [--runs R] [--count N] [--rounds T] [--seconds S]" >&2; exit 2 ;;
  esac
done

# RelWithDebInfo (-O2), the project's default build type, so that the figures stay comparable
# with the earlier runs on this page.
build=build/benchmarks  # not build/bench: that is the bench/ folder of the build/ tree
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$jobs" --target dxlemu reply_latency throughput pty_echo scale

page=docs/benchmarks.md
begin='<!-- bench.sh: begin -->'
end='<!-- bench.sh: end -->'
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

command=("$build/bench/reply_latency" --dxlemu "$build/emulator/dxlemu" --count "$count"
         --echo "$build/bench/pty_echo")
throughput=("$build/bench/throughput" --dxlemu "$build/emulator/dxlemu" --echo "$build/bench/pty_echo"
            --seconds "$seconds" --runs "$rounds")
scale=("$build/bench/scale" --dxlemu "$build/emulator/dxlemu" --seconds "$seconds")
# The first CPU this process may use (a container may not offer CPU 0).
cpu=$(awk '/^Cpus_allowed_list/ { split($2, a, /[-,]/); print a[1] }' /proc/self/status)
pinned=(--cpu "$cpu")
# run_into NAME COMMAND...: runs COMMAND with stdout into $out/NAME.md; its log goes to
# $out/NAME.log and is shown only when it fails.
run_into() {
  local name=$1
  shift
  if ! "$@" >"$out/$name.md" 2>"$out/$name.log"; then
    cat "$out/$name.log" >&2
    exit 1
  fi
}
# measure NAME [OPTIONS...]: one reply_latency run.
measure() {
  local name=$1
  shift
  run_into "$name" "${command[@]}" "$@"
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for r in $(seq 1 "$runs"); do
  echo "bench.sh: run $r of $runs" >&2
  measure "free-$r"
  measure "pinned-$r" "${pinned[@]}"
done
echo "bench.sh: throughput" >&2
run_into throughput "${throughput[@]}"
echo "bench.sh: scale" >&2
run_into scale "${scale[@]}"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

# summary FILE...: one row per baud and instruction with the median and p99 of every run (FILE),
# and how many runs met the target: |median| <= 20 us and p99 <= 100 us at 1 Mbit/s.
summary() {
  awk -F'|' -v runs="$runs" '
    function trim(s) { gsub(/^ +| +$/, "", s); return s }
    function abs(x) { return x < 0 ? -x : x }
    FNR <= 2 || NF < 11 { next }
    {
      key = trim($2) " | " trim($3)
      if (!(key in seen)) { seen[key] = 1; order[++n] = key }
      med = trim($9); p99 = trim($10)
      meds[key] = meds[key] (meds[key] == "" ? "" : " / ") med
      p99s[key] = p99s[key] (p99s[key] == "" ? "" : " / ") p99
      if (med != "-" && abs(med + 0) <= 20 && p99 + 0 <= 100) { ok[key]++ }
    }
    END {
      print "| baud | instruction | median per run (µs) | p99 per run (µs) | \\|median\\| ≤ 20, p99 ≤ 100 (the target at 1 M) |"
      print "|---:|---|---|---|---|"
      for (i = 1; i <= n; ++i) {
        k = order[i]
        print "| " k " | " meds[k] " | " p99s[k] " | " (ok[k] + 0) " of " runs " runs |"
      }
    }' "$@"
}

# value FILE LABEL: the value column of the row whose first column is LABEL in a two-column table.
value() {
  awk -F'|' -v label="$2" '{ gsub(/^ +| +$/, "", $2) } $2 == label { gsub(/^ +| +$/, "", $3); print $3; exit }' "$1"
}
# column FILE LABEL N: field N of the first row whose first column is LABEL.
column() {
  awk -F'|' -v label="$2" -v n="$3" '{ gsub(/^ +| +$/, "", $2) } $2 == label { gsub(/^ +| +$/, "", $n); print $n; exit }' "$1"
}
# timing_met FILE...: how many (instruction, run) pairs at 1 Mbit/s met |median| <= 20 us and
# p99 <= 100 us, as "M of N".
timing_met() {
  awk -F'|' '
    function abs(x) { return x < 0 ? -x : x }
    FNR <= 2 || NF < 11 { next }
    $3 ~ /bare timed responder/ { next }
    $2 + 0 == 1000000 { n++; if ($9 !~ /-  *$/ && abs($9 + 0) <= 20 && $10 + 0 <= 100) ok++ }
    END { print (ok + 0) " of " (n + 0) }' "$@"
}
# cpu_ratio FILE...: per run (FILE), dxlemu's CPU per Read 4 B round trip at 1 Mbit/s over the
# bare timed responder's in the same run, as "R1 / R2 ...".
cpu_ratio() {
  local f ratios=()
  for f in "$@"; do
    ratios+=("$(awk -F'|' '
      function trim(s) { gsub(/^ +| +$/, "", s); return s }
      $2 + 0 == 1000000 && trim($3) == "Read 4 B" { dx = trim($12) }
      $2 + 0 == 1000000 && trim($3) == "Read 4 B, bare timed responder" { bare = trim($12) }
      END { if (dx == "" || bare == "" || bare + 0 == 0) print "-"; else printf "%.2f", dx / bare }' "$f")")
  done
  local IFS=/
  echo "${ratios[*]}" | sed 's|/| / |g'
}
# met VALUE TARGET-AWK-CONDITION: "yes" or "no".
met() {
  awk -v v="$1" "BEGIN { print (($2) ? \"yes\" : \"no\") }"
}
# targets: every figure next to its target, from the outputs of this run.
targets() {
  local free_met pinned_met ratio correct_sync correct_ping ports idle_open idle_closed serving t
  free_met=$(timing_met "$out"/free-*.md)
  pinned_met=$(timing_met "$out"/pinned-*.md)
  ratio=$(column "$out/throughput.md" dxlemu 5)
  correct_sync=$(column "$out/scale.md" "Sync Read 4 B × 253 (shuffled list)" 6)
  correct_ping=$(column "$out/scale.md" "broadcast Ping × 253" 6)
  ports=$(value "$out/scale.md" "ports where every servo answered a Ping")
  idle_open=$(value "$out/scale.md" "idle, ports open: dxlemu CPU")
  idle_closed=$(value "$out/scale.md" "idle, ports closed: dxlemu CPU")
  echo "| figure | target | this run | met |"
  echo "|---|---|---|---|"
  echo "| reply timing at 1 Mbit/s, any CPU: (instruction, run) pairs with \\|median\\| ≤ 20 µs and p99 ≤ 100 µs | all | $free_met | $(met "$free_met" 'split(v, a, " of ") && a[1] == a[2]') |"
  echo "| reply timing at 1 Mbit/s, pinned to one CPU: the same | all | $pinned_met | $(met "$pinned_met" 'split(v, a, " of ") && a[1] == a[2]') |"
  echo "| realtime CPU per Read 4 B round trip at 1 Mbit/s over a bare timed responder's (\`pty_echo --reply-after-us\`), per run | ≈ 1 | $(cpu_ratio "$out"/free-*.md) | - |"
  echo "| Read 4 B round trips/s under \`--timing fast\` against a bare PTY program (median of $rounds rounds) | ≥ 0.8 | $ratio | $(met "$ratio" 'v + 0 >= 0.8') |"
  echo "| 253 servos: Sync Read replies correct and in order | all | $correct_sync | $(met "$correct_sync" 'split(v, a, " of ") && a[1] == a[2]') |"
  echo "| 253 servos: broadcast Ping replies correct and in order | all | $correct_ping | $(met "$correct_ping" 'split(v, a, " of ") && a[1] == a[2]') |"
  echo "| 32 ports in one process: ports where every servo answered | all | $ports | $(met "$ports" 'split(v, a, " of ") && a[1] == a[2]') |"
  echo "| idle CPU, 32 ports open and no client | ≈ 0 % | ${idle_open%% (*} | $(met "$idle_open" 'v + 0 < 0.5') |"
  echo "| idle CPU, 32 ports after the clients closed them | ≈ 0 % | ${idle_closed%% (*} | $(met "$idle_closed" 'v + 0 < 0.5') |"
  echo "| peak RSS, 253 servos on one bus / 32 ports × 6 servos | (none) | $(value "$out/scale.md" "peak RSS after start / after the chains") / $(value "$out/scale.md" "peak RSS after start / after serving") | - |"
  serving=$(value "$out/scale.md" "serving 32 ports: dxlemu CPU")
  echo "| CPU serving 32 ports (a Read 4 B round trip on each, back to back) | (none) | ${serving%% (*} of one CPU | - |"
  for t in "dxlemu + trace file" "dxlemu + pcap file" "dxlemu + trace subscriber" "dxlemu + stats client"; do
    echo "| ${t#dxlemu + }: round trips/s against a bare PTY (CPU per round trip) | (none; without it: $ratio) | $(column "$out/throughput.md" "$t" 5) ($(column "$out/throughput.md" "$t" 12) µs, without: $(column "$out/throughput.md" dxlemu 12) µs) | - |"
  done
}

{
  echo "$begin"
  echo
  echo "Written by \`scripts/bench.sh --runs $runs --count $count --rounds $rounds --seconds $seconds\` on $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "at commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown) (plus any local changes), in $(( SECONDS / 60 )) min $(( SECONDS % 60 )) s"
  echo "including the build."
  echo
  echo "- Machine: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'),"
  echo "  Linux $(uname -r)$(grep -qw hypervisor /proc/cpuinfo && echo ", a virtual machine (CPU flag \`hypervisor\`)")."
  echo "- Load average (1, 5, 15 min): $load_before before, $load_after after."
  echo "- Build: \`cmake -S . -B $build ${generator[*]} -DCMAKE_BUILD_TYPE=RelWithDebInfo && cmake --build $build --target dxlemu reply_latency throughput pty_echo scale\`."
  echo "- Reply timing, each run: \`${command[*]}\`, then the same with \`${pinned[*]}\`."
  echo "- Throughput: \`${throughput[*]}\`."
  echo "- Scale: \`${scale[*]}\`."
  echo
  echo "### Against the targets"
  echo
  targets
  for mode in free pinned; do
    if [ $mode = free ]; then
      title="any CPU"
    else
      title="pinned to CPU $cpu"
    fi
    echo
    echo "### Reply timing, $title: summary against the target"
    echo
    summary "$out/$mode"-*.md
    for r in $(seq 1 "$runs"); do
      echo
      echo "#### $title, run $r"
      echo
      cat "$out/$mode-$r.md"
    done
  done
  echo
  echo "### Throughput against a bare PTY, and the cost of the trace and the control API"
  echo
  cat "$out/throughput.md"
  echo
  echo "### Scale"
  echo
  cat "$out/scale.md"
  echo
  echo "$end"
} >"$out/generated.md"

if [ -f "$page" ] && grep -qF "$begin" "$page" && grep -qF "$end" "$page"; then
  awk -v begin="$begin" -v end="$end" -v gen="$out/generated.md" '
    $0 == begin { while ((getline line < gen) > 0) print line; skip = 1; next }
    $0 == end { skip = 0; next }
    !skip { print }' "$page" >"$out/page.md"
else
  { echo "# Benchmarks"; echo; cat "$out/generated.md"; } >"$out/page.md"
fi
cp "$out/page.md" "$page"
echo "bench.sh: wrote $page" >&2
