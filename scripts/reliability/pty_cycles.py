#!/usr/bin/env python3
"""Reliability: a client opens and closes the port's pseudo-terminal over and over.

    python3 scripts/reliability/pty_cycles.py [--quick] [--cycles N]

Controllers open a serial port, talk a little and close it again, many times a day (pyserial
users often open the port per script run). Each cycle here opens dxl0's link the way such a
client does, sometimes sends a Ping and reads the reply (sometimes sends one and closes without
reading it, leaving the reply behind: it may reach the next open after that open flushed the
line, as a servo's reply reaches a controller that reopened its port within the reply time;
such late answers are allowed, counted, and nothing else), and closes. Afterwards:

- the daemon holds as many file descriptors as before (nothing leaks per open or close);
- it still answers a Ping on a fresh open;
- it uses (almost) no CPU once left alone: a hung-up PTY must not make it spin.

The daemon runs under manual timing: each reply goes out as soon as its Ping is read, and none
is dropped as late however busy the machine is, so a missing answer is the PTY handling's fault.

Exit status 0 when all holds, 1 (with `FAILED: ...`) when not.
"""
from __future__ import annotations

import fcntl
import os
import random
import termios
import time
from collections import Counter

from common import (check, cpu_seconds, fd_targets, idle_cpu_percent, open_fds, parser, run,
                    summary)
from dxlemu import Emulator
from dxlemu.protocol import PING, Port, Status, packet2

SERVOS = (1, 2, 3)
XM430_MODEL_NUMBER = 1020
# Idle CPU above this share of one CPU counts as spinning (a timer or a PTY hang-up loop).
IDLE_CPU_LIMIT_PERCENT = 1.0
# How long the daemon may take to handle the last hang-up before a descriptor counts as leaked.
REAP_TIMEOUT_S = 5.0


def pyserial_like_open(path: str) -> int:
    """Opens the line as pyserial's Serial(path, 57600) does: non-blocking open, exclusive
    lock, raw 8N1 at the rate, input flushed. Returns the descriptor."""
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    try:
        fcntl.ioctl(fd, termios.TIOCEXCL)
        attr = termios.tcgetattr(fd)
        attr[0] = attr[1] = attr[3] = 0
        attr[2] = termios.CS8 | termios.CREAD | termios.CLOCAL
        attr[4] = attr[5] = termios.B57600
        attr[6][termios.VMIN], attr[6][termios.VTIME] = 0, 0
        termios.tcsetattr(fd, termios.TCSANOW, attr)
        termios.tcflush(fd, termios.TCIFLUSH)
    except BaseException:
        os.close(fd)
        raise
    return fd


def is_ping_reply(status: Status, servo: int) -> bool:
    """True when `status` is servo `servo`'s answer to a Ping."""
    return (status.id == servo and status.error == 0 and
            int.from_bytes(status.params[:2], "little") == XM430_MODEL_NUMBER)


def ping_and_check(port: Port, servo: int, cycle: int, outstanding: Counter) -> int:
    """Pings `servo` and waits for its answer. Every Ping sent in this run is counted in
    `outstanding` (by ID) until an answer of that ID is read: a Ping sent in a cycle that closed
    without reading may be answered after a later cycle's open flushed the line (as a servo
    answers a controller that reopened its port within the reply time), and then reaches that
    later cycle first. So every status read must be the answer to a Ping of that ID still
    outstanding; nothing else may come. Returns how many came before one of `servo`."""
    outstanding[servo] += 1
    port.write(packet2(servo, PING))
    late = 0
    while True:
        status = port.status2(timeout=2.0)
        check(status is not None, f"cycle {cycle}: no reply to a Ping of servo {servo}")
        check(is_ping_reply(status, status.id) and outstanding[status.id] > 0,
              f"cycle {cycle}: wrong reply to a Ping of servo {servo}: {status} (Pings not yet "
              f"answered: {dict(+outstanding)})")
        outstanding[status.id] -= 1
        if status.id == servo:
            return late
        late += 1


def one_cycle(link: str, cycle: int, rng: random.Random, tally: dict[str, int],
              outstanding: Counter) -> None:
    """One open-use-close cycle, chosen at random among what clients do; `outstanding` as in
    ping_and_check."""
    kind = rng.choices(("open_close", "pyserial_open_close", "ping", "ping_unread"),
                       weights=(3, 3, 3, 1))[0]
    tally[kind] += 1
    if kind == "open_close":  # a probe: open and close at once, no settings
        os.close(os.open(link, os.O_RDWR | os.O_NOCTTY))
    elif kind == "pyserial_open_close":
        os.close(pyserial_like_open(link))
    elif kind == "ping":
        with Port(link) as port:
            servo = rng.choice(SERVOS)
            tally["late_answers"] += ping_and_check(port, servo, cycle, outstanding)
    else:  # the reply comes back to a closed line (or to the next open, if it is quick)
        fd = pyserial_like_open(link)
        servo = rng.choice(SERVOS)
        os.write(fd, packet2(servo, PING))
        os.close(fd)
        outstanding[servo] += 1


def main() -> None:
    args = parser(__doc__.split("\n\n")[0]).parse_args()
    # --quick: about 1200 of them open, Ping and read the answer (--seed 1: 1176).
    cycles = 4000 if args.quick else 10_000
    idle_seconds = 1.0 if args.quick else 5.0
    rng = random.Random(args.seed)
    tally = {"open_close": 0, "pyserial_open_close": 0, "ping": 0, "ping_unread": 0,
             "late_answers": 0}
    outstanding: Counter = Counter()
    with Emulator(timing="manual") as emulator:
        pid = emulator.process.proc.pid
        # Warm up: the first opens may allocate what the daemon then keeps (epoll entries).
        for cycle in range(20):
            with Port(emulator.link) as port:
                ping_and_check(port, 1, cycle, outstanding)
        fds_before, targets_before = open_fds(pid), fd_targets(pid)
        cpu_start, start = cpu_seconds(pid), time.monotonic()
        for cycle in range(cycles):
            one_cycle(emulator.link, cycle, rng, tally, outstanding)
        elapsed = time.monotonic() - start
        busy_cpu = cpu_seconds(pid) - cpu_start
        # The daemon handles the last close (and a reply left unread) when it next runs: wait
        # for that, and no longer than it takes; a descriptor leaked stays counted.
        deadline = time.monotonic() + REAP_TIMEOUT_S
        while (fds_after := open_fds(pid)) != fds_before and time.monotonic() < deadline:
            time.sleep(0.01)
        check(fds_after == fds_before,
              f"the daemon held {fds_before} descriptors before and {fds_after} after "
              f"{cycles} cycles:\nbefore {targets_before}\nafter  {fd_targets(pid)}")
        with Port(emulator.link) as port:
            for servo in SERVOS:
                ping_and_check(port, servo, cycles, outstanding)
        idle = idle_cpu_percent(pid, idle_seconds)
        check(idle <= IDLE_CPU_LIMIT_PERCENT,
              f"the daemon used {idle:.2f} % of a CPU while idle for {idle_seconds} s after the "
              f"cycles (limit {IDLE_CPU_LIMIT_PERCENT} %)")
        check(emulator.running, "the daemon exited")
        code = emulator.stop()
        check(code == 0, f"the daemon did not stop cleanly: exit status {code}\n{emulator.stderr}")
    summary("pty_cycles", [
        ("cycles", f"{cycles} in {elapsed:.2f} s ({cycles / elapsed:.0f}/s)"),
        ("kinds", ", ".join(f"{kind} {count}" for kind, count in tally.items()
                            if kind != "late_answers")),
        ("late answers", f"{tally['late_answers']} answers to unread Pings came after the "
                         "next open flushed the line (allowed: see ping_and_check)"),
        ("daemon fds", f"before {fds_before}, after {fds_after}"),
        ("daemon CPU during cycles",
         f"{busy_cpu:.2f} s ({100 * busy_cpu / elapsed:.1f} % of one CPU)"),
        ("daemon CPU idle after", f"{idle:.3f} % of one CPU over {idle_seconds:.0f} s"),
        ("answers after", f"Ping of servos {', '.join(map(str, SERVOS))}: ok; clean stop: exit 0"),
    ])


if __name__ == "__main__":
    run(main)
