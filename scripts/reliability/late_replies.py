#!/usr/bin/env python3
"""Reliability: a DynamixelSDK-like client on a machine busy with compile jobs.

    python3 scripts/reliability/late_replies.py [--quick] [--jobs N] [--count N] [--rounds R]
                                                [--before BIN] [--baud BPS]

dxlemu serves three XM430-W350 (IDs 1 ~ 3) at --baud (default 1 Mbit/s) under realtime timing.
Beside it, --jobs compile jobs (default 4; `c++ -O2` of a file that includes much of the
standard library, again and again) keep both CPUs busy. A client does what DynamixelSDK's
`txRxPacket` does for a Read: discard stale input (`clearPort`), write the instruction, wait for
the status at most the SDK's packet timeout (the status's wire time + twice its 16 ms latency
timer + 2 ms, about 34 ms). It cycles through three reads of servo 1, each with a status of its
own length: Present Position (132, 4 bytes), Model Number (0, 2 bytes: 1020) and ID (7, 1 byte:
1), so a status that answers an earlier request is caught: it is counted as misattributed.

The same client then runs against a bare-PTY responder in the same conditions: a process that
answers every Read at once with the status it asks for, doing no other work, the floor of what
the machine adds to a round trip. Figures per round (--rounds, default 2; with --before BIN the
two binaries alternate within each round):

- timeouts: no status within the SDK's timeout (on a real bus, a lost reply);
- misattributed: a status that was not the answer to the request (must be 0);
- dxlemu: how late each status came against its modelled time (docs/bus.md "Reply timing");
  the bare responder: its whole round trip (it models nothing, so all of it is the machine's);
- dropped: statuses the daemon dropped as later than --late-reply-limit-ms (its `stats`).

--window-ms W waits W ms instead of the SDK's timeout, as a fast control loop does (ROS 2's
dynamixel_hardware_interface at 200 Hz: 5 ms); give dxlemu a limit under it then, e.g.
`--arg=--late-reply-limit-ms --arg=3` (--arg goes to the first binary only).

Exit status 0 when no status from dxlemu was misattributed, 1 (`FAILED: ...`) when one was;
with --window-ms, when dxlemu had more than the bare PTY in the same round (a window shorter
than the delays the machine itself adds lets even a responder that does nothing be misread). --quick (the
ctest run): 2 jobs, 300 reads, one round.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from common import check, parser, percentile, run

import dxlemu
from dxlemu.codec import frame_status2, packet2
from dxlemu.port import Port

READ = 0x02
SERVO = 1
# (address, length, the value a factory XM430-W350 with ID 1 returns, or None when it moves).
REQUESTS = ((132, 4, None), (0, 2, 1020), (7, 1, SERVO))
# The reply timing of docs/bus.md for these servos at factory settings: processing, then Return
# Delay Time 250 (500 µs).
PROCESSING_S = 50e-6
RETURN_DELAY_S = 500e-6
# DynamixelSDK's PortHandler: LATENCY_TIMER 16 ms, timeout = bytes x time per byte + 2 x 16 + 2 ms.
SDK_LATENCY_TIMER_MS = 16.0

# A translation unit that takes a few seconds at -O2: the compile job.
COMPILE_JOB = """
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>
int main(int argc, char** argv) {
  std::map<std::string, std::vector<std::regex>> m;
  m[argv[0]].emplace_back(argc > 1 ? argv[1] : ".*");
  std::ostringstream out;
  for (const auto& [k, v] : m) out << k << v.size();
  std::unordered_map<std::string, std::filesystem::path> p{{out.str(), argv[0]}};
  std::cout << p.size() << std::endl;
}
"""

# The bare-PTY responder: a PTY like dxlemu's, and for every whole Protocol 2.0 Read a status of
# the asked length, at once (the values servo 1 would give, so the client checks it alike).
RESPONDER = r"""
import os, sys, termios, tty
sys.path.insert(0, sys.argv[1])
from dxlemu.codec import crc16
master, slave = os.openpty()
tty.setraw(slave)
print(os.ttyname(slave), flush=True)
values = {0: 1020, 7: 1}
buffer = b""
while True:
    buffer += os.read(master, 4096)
    while len(buffer) >= 14:
        start = buffer.find(b"\xff\xff\xfd\x00")
        if start < 0:
            buffer = buffer[-3:]
            break
        buffer = buffer[start:]
        if len(buffer) < 14:
            break
        address = buffer[8] | buffer[9] << 8
        length = buffer[10] | buffer[11] << 8
        ident = buffer[4]
        buffer = buffer[14:]
        data = values.get(address, 2048).to_bytes(4, "little")[:length].ljust(length, b"\0")
        body = bytes([0xFF, 0xFF, 0xFD, 0x00, ident]) + (length + 4).to_bytes(2, "little")
        body += bytes([0x55, 0]) + data
        os.write(master, body + crc16(body).to_bytes(2, "little"))
"""


def wire_s(count: int, baud: int) -> float:
    """Seconds `count` bytes take on the line (10 bits each)."""
    return count * 10.0 / baud


@dataclass
class Figures:
    """One client run against one responder."""
    reads: int = 0
    timeouts: int = 0
    misattributed: int = 0
    late_s: list[float] = field(default_factory=list)  # against the modelled time (or 0)
    dropped: int | None = None  # from the daemon's stats; None for the bare responder

    def row(self, name: str) -> str:
        def ms(q: float) -> str:
            return f"{percentile(self.late_s, q) * 1e3:.2f}" if self.late_s else "-"
        peak = f"{max(self.late_s) * 1e3:.2f}" if self.late_s else "-"
        dropped = "-" if self.dropped is None else str(self.dropped)
        return (f"| {name} | {self.reads} | {self.timeouts} | {self.misattributed} | {ms(0.5)} | "
                f"{ms(0.99)} | {peak} | {dropped} |")


def sdk_read(port: Port, address: int, length: int, baud: int,
             window_ms: float | None) -> tuple[object, float]:
    """One DynamixelSDK-style Read of servo 1: (status or None, round-trip seconds). The wait is
    the SDK's packet timeout, or `window_ms` when given (a control loop's receive window)."""
    instruction = packet2(SERVO, READ, address.to_bytes(2, "little") + length.to_bytes(2, "little"))
    status_size = 11 + length
    timeout_s = (wire_s(status_size, baud) * 1e3 + 2 * SDK_LATENCY_TIMER_MS + 2.0) / 1e3
    if window_ms is not None:
        timeout_s = window_ms / 1e3
    port.flush_input()  # clearPort()
    sent = time.monotonic()
    port.write(instruction)
    status = port.status2(timeout_s)
    return status, time.monotonic() - sent


def client(path: str, baud: int, count: int, modelled: bool, window_ms: float | None) -> Figures:
    """`count` reads cycling through REQUESTS. With `modelled`, lateness is the round trip less
    the reply timing a real servo has; without (the bare responder), the whole round trip."""
    figures = Figures()
    with Port(path, baud) as port:
        for i in range(count):
            address, length, value = REQUESTS[i % len(REQUESTS)]
            figures.reads += 1
            try:
                status, rtt = sdk_read(port, address, length, baud, window_ms)
            except dxlemu.CommError:
                status, rtt = None, 0.0  # a torn packet: on a real bus, a garbled reply
            if status is None:
                figures.timeouts += 1
                continue
            got = int.from_bytes(status.params, "little")
            if status.id != SERVO or len(status.params) != length or (
                    value is not None and got != value):
                figures.misattributed += 1
                continue
            model = (wire_s(14, baud) + PROCESSING_S + RETURN_DELAY_S + wire_s(11 + length, baud)
                     if modelled else 0.0)
            figures.late_s.append(rtt - model)
    return figures


def against_dxlemu(binary: str, baud: int, count: int, extra: list[str],
                   window_ms: float | None) -> Figures:
    with dxlemu.Emulator(binary=binary, servos=["xm430-w350:1-3"], baud=baud,
                         timing="realtime", args=extra, timeout=60) as emulator:
        figures = client(emulator.pty, baud, count, modelled=True, window_ms=window_ms)
        lateness = emulator.control.stats()["dxl0"].get("lateness")
        figures.dropped = lateness["dropped"] if lateness else None
    return figures


def against_bare_pty(baud: int, count: int, window_ms: float | None) -> Figures:
    responder = subprocess.Popen(
        [sys.executable, "-c", RESPONDER, str(Path(dxlemu.__file__).resolve().parents[1])],
        stdout=subprocess.PIPE, text=True)
    try:
        path = responder.stdout.readline().strip()
        check(bool(path), "the bare-PTY responder did not start")
        return client(path, baud, count, modelled=False, window_ms=window_ms)
    finally:
        responder.kill()
        responder.wait()


class CompileJobs:
    """`jobs` processes compiling COMPILE_JOB over and over, until stopped."""

    def __init__(self, jobs: int):
        compiler = shutil.which("c++") or shutil.which("g++")
        check(compiler is not None, "no C++ compiler (c++ or g++) for the compile jobs "
                                    "(Debian package g++)")
        self._dir = tempfile.TemporaryDirectory(prefix="dxlemu-load-")
        source = Path(self._dir.name) / "job.cpp"
        source.write_text(COMPILE_JOB)
        loop = f'while :; do "{compiler}" -std=c++20 -O2 -c "{source}" -o /dev/null; done'
        self._procs = [subprocess.Popen(["sh", "-c", loop], start_new_session=True,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                       for _ in range(jobs)]

    def stop(self) -> None:
        for proc in self._procs:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait()
        self._dir.cleanup()


def main() -> None:
    args = parser(__doc__.splitlines()[0])
    args.add_argument("--jobs", type=int, default=4, help="compile jobs beside it (default 4)")
    args.add_argument("--count", type=int, default=2000, help="reads per run (default 2000)")
    args.add_argument("--rounds", type=int, default=2, help="rounds (default 2)")
    args.add_argument("--baud", type=int, default=1_000_000, help="bit/s (default 1000000)")
    args.add_argument("--before", help="a second dxlemu binary, run alternately with the first")
    args.add_argument("--arg", action="append", default=[],
                      help="an argument for the first binary's `dxlemu run`, not --before's "
                           "(repeatable)")
    args.add_argument("--window-ms", type=float,
                      help="wait this long for each status instead of the SDK's timeout (a "
                           "control loop's receive window, e.g. 5 at 200 Hz)")
    options = args.parse_args()
    if options.quick:
        options.jobs, options.count, options.rounds = 2, 300, 1
    binaries = [("dxlemu", dxlemu.find_binary())]
    if options.before:
        binaries.insert(0, ("before", options.before))
    load = CompileJobs(options.jobs)
    rows = []
    misattributed = 0  # dxlemu's, beyond what the bare PTY shows in the same round
    try:
        time.sleep(1.0)  # let the jobs get going
        for round_ in range(1, options.rounds + 1):
            for name, binary in binaries:
                figures = against_dxlemu(binary, options.baud, options.count,
                                         options.arg if name == "dxlemu" else [],
                                         options.window_ms)
                if name == "dxlemu":
                    ours = figures.misattributed
                rows.append(figures.row(f"{name}, round {round_}"))
            bare = against_bare_pty(options.baud, options.count, options.window_ms)
            rows.append(bare.row(f"bare PTY, round {round_}"))
            # Within the SDK's timeout nothing may be misattributed; within a window shorter
            # than what the machine adds, even the bare PTY's replies are, and dxlemu can only
            # be held to doing no worse than it.
            allowed = 0 if options.window_ms is None else bare.misattributed
            misattributed += max(0, ours - allowed)
            load_average = os.getloadavg()[0]
            rows.append(f"| (load average {load_average:.2f}) | | | | | | | |")
    finally:
        load.stop()
    wait = (f"waiting {options.window_ms:g} ms" if options.window_ms is not None
            else "waiting as the SDK does")
    print(f"\n{options.jobs} compile jobs beside a client doing {options.count} DynamixelSDK-style "
          f"reads at {options.baud} bit/s, {wait}, {os.cpu_count()} CPUs; dxlemu run "
          f"{' '.join(options.arg) or '(defaults)'}; lateness in ms (dxlemu: against the modelled "
          "reply time; bare PTY: the whole round trip)\n")
    print("| run | reads | timeouts | misattributed | p50 | p99 | max | dropped |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        print(row)
    sys.stdout.flush()
    check(misattributed == 0, f"{misattributed} statuses were taken for the answer to a later "
                              "request" + ("" if options.window_ms is None else
                                           ", beyond the bare PTY's"))


if __name__ == "__main__":
    run(main)
