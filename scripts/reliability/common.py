"""Helpers shared by the reliability scripts (scripts/reliability/*.py).

Each script proves one thing about a running `dxlemu run` (it keeps working, it loses nothing)
and prints its figures. They need only the standard library and the project's Python package
(python/dxlemu), found here relative to this file. The binary is $DXLEMU_BIN, else `dxlemu` on
PATH, else the checkout's build (dxlemu.find_binary).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Callable, Iterable, Sequence

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))  # the dxlemu package

import dxlemu  # noqa: E402,F401  (re-exported for the scripts)

# Clock ticks per second, for /proc/PID/stat's utime and stime.
_CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


class Failure(Exception):
    """An invariant that did not hold: the script prints it and exits 1."""


def check(condition: bool, message: str) -> None:
    """Fails the script with `message` unless `condition` holds."""
    if not condition:
        raise Failure(message)


def parser(description: str) -> argparse.ArgumentParser:
    """An argument parser with the options every script takes."""
    result = argparse.ArgumentParser(description=description)
    result.add_argument("--quick", action="store_true",
                        help="small counts (the ctest runs): a few seconds")
    result.add_argument("--seed", type=int, default=1,
                        help="seed of the script's random choices (default 1)")
    return result


# The daemon's process, seen through /proc.

def open_fds(pid: int) -> int:
    """How many file descriptors process `pid` holds now."""
    return len(os.listdir(f"/proc/{pid}/fd"))


def fd_targets(pid: int) -> list[str]:
    """What each of `pid`'s descriptors points at (for a message when they leak)."""
    targets = []
    for fd in sorted(os.listdir(f"/proc/{pid}/fd"), key=int):
        try:
            targets.append(f"{fd}->{os.readlink(f'/proc/{pid}/fd/{fd}')}")
        except OSError:
            pass  # closed meanwhile
    return targets


def cpu_seconds(pid: int) -> float:
    """User plus system CPU time process `pid` has used, in seconds."""
    with open(f"/proc/{pid}/stat") as f:
        # The command name (field 2) may hold spaces: split after its closing parenthesis.
        fields = f.read().rsplit(")", 1)[1].split()
    utime, stime = int(fields[11]), int(fields[12])  # fields 14 and 15 of proc(5)
    return (utime + stime) / _CLOCK_TICKS


def rss_kib(pid: int) -> int:
    """Resident set size of process `pid` (VmRSS), in KiB."""
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise Failure(f"no VmRSS in /proc/{pid}/status")


def idle_cpu_percent(pid: int, seconds: float) -> float:
    """The share of one CPU process `pid` uses while left alone for `seconds`."""
    start_cpu, start = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return 100.0 * (cpu_seconds(pid) - start_cpu) / (time.monotonic() - start)


def heard(control: dxlemu.Control, count: int, port: str = "dxl0", timeout: float = 10.0) -> dict:
    """Asks `stats` until the daemon has read `count` bytes on `port` (its `bytes_in`); returns
    that port's counters. Everything the daemon does at once with those bytes is done by then,
    so they are stamped before a manual clock is stepped. Failure after `timeout` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        stats = control.stats(port)[port]
        if stats["bytes_in"] >= count:
            return stats
        check(time.monotonic() < deadline,
              f"the daemon read {stats['bytes_in']} of {count} bytes on {port} in {timeout} s")


def alive(pid: int) -> bool:
    """True while process `pid` exists and is not a zombie."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


# Figures.

def percentile(samples: Sequence[float], fraction: float) -> float:
    """The nearest-rank percentile of `samples` (fraction 0.5 is the median)."""
    ordered = sorted(samples)
    if not ordered:
        return float("nan")
    rank = max(0, min(len(ordered) - 1, round(fraction * len(ordered) + 0.5) - 1))
    return ordered[rank]


def latency_ms(samples: Sequence[float]) -> str:
    """Count, p50, p90, p99 and max of latencies given in seconds, as one line in ms."""
    if not samples:
        return "no samples"
    parts = [f"{name} {percentile(samples, q) * 1e3:.3f}"
             for name, q in (("p50", 0.5), ("p90", 0.9), ("p99", 0.99))]
    return f"n={len(samples)} " + " ".join(parts) + f" max {max(samples) * 1e3:.3f} ms"


def summary(title: str, rows: Iterable[tuple[str, object]]) -> None:
    """Prints the figures of a run as an aligned block (copied into docs/reliability.md)."""
    rows = list(rows)
    width = max(len(name) for name, _ in rows)
    print(f"\n== {title} ==")
    for name, value in rows:
        print(f"  {name.ljust(width)}  {value}")
    sys.stdout.flush()


def run(main: Callable[[], None]) -> None:
    """Runs a script's `main`: exit 0 when every invariant held, else prints `FAILED: ...`
    and exits 1 (2 when the script itself broke, with its traceback)."""
    try:
        main()
    except Failure as failure:
        print(f"FAILED: {failure}", file=sys.stderr)
        sys.exit(1)
    except KeyboardInterrupt:
        sys.exit(130)
    except Exception:  # noqa: BLE001  a broken script is not a broken daemon: say which
        traceback.print_exc()
        print("FAILED: the script raised an exception (see above)", file=sys.stderr)
        sys.exit(2)
    sys.exit(0)
