#!/usr/bin/env python3
"""Reliability: `kill -9` at any moment around an EEPROM write never breaks the state file.

    python3 scripts/reliability/state_kill.py [--quick] [--kills N] [--window-ms MS]

With `--state FILE` dxlemu rewrites FILE atomically whenever a servo's EEPROM changes
(docs/config.md "State file"). Each round here:

1. starts `dxlemu run --state FILE` (one XM430-W350, --timing manual: replies at once, none
   dropped as late on a busy machine): it must start, i.e. the file left by the previous kill
   loads, and the servo must hold the limits the file holds;
2. writes Max Position Limit and Min Position Limit (addresses 48 ~ 55, two 4-byte EEPROM
   items in one Write) to new values over the bus;
3. kills the daemon with SIGKILL at a random moment from 0 to --window-ms after sending the
   Write (before, during or after the reply and the file's rewrite);
4. reads FILE as JSON: both items must hold the old pair or the new pair, never anything else
   (not a mix of the two, not a torn number, not an unreadable file).

5. when the Write's status had reached the client before the kill, the file must hold the new
   pair: an acknowledged EEPROM write is never lost (the daemon saves before it replies).

A kill during a save leaves the daemon's temporary file (FILE.tmp.PID); the next daemon's first
save removes it, so they never pile up: after a last, clean start and Write, none may remain.

It counts rounds that kept the old pair and the new one. Exit status 0 when every round held, 1
(with `FAILED: ...`) when not.
"""
from __future__ import annotations

import glob
import json
import os
import random
import select
import shutil
import signal
import tempfile
import time

from common import Failure, check, parser, run, summary
from dxlemu import DaemonError, DaemonProcess
from dxlemu.protocol import READ, WRITE, Port, frame_status2, packet2

SERVO = 1
LIMITS_ADDRESS, LIMITS_SIZE = 48, 8  # Max Position Limit (48, 4 bytes), Min Position Limit (52, 4)
INITIAL = (4095, 0)  # the XM430-W350's factory limits


def limits_bytes(pair: tuple[int, int]) -> bytes:
    """The 8 bytes of (max, min) as the control table holds them."""
    return pair[0].to_bytes(4, "little") + pair[1].to_bytes(4, "little")


def limits_in_file(path: str) -> tuple[int, int]:
    """(max, min) position limit of the one servo in state file `path`; Failure when the file
    is not a state file a daemon could have written."""
    try:
        with open(path, encoding="utf-8") as f:
            state = json.load(f)
        check(state.get("format") == "dxlemu-state", f"{path}: format is {state.get('format')!r}")
        eeprom = state["ports"]["dxl0"][0]["eeprom"]
        return eeprom["max_position_limit"], eeprom["min_position_limit"]
    except (OSError, ValueError, KeyError, IndexError, TypeError) as error:
        raise Failure(f"the state file {path} does not load: {error!r}") from error


def start_daemon(directory: str, state: str) -> DaemonProcess:
    """`dxlemu run --state STATE` with one XM430-W350 on a link in `directory`."""
    return DaemonProcess(["--link", os.path.join(directory, "dxl0"),
                          "--control", os.path.join(directory, "control.sock"),
                          "--servo", f"xm430-w350:{SERVO}", "--timing", "manual",
                          "--state", state, "--log-level", "error"])


def read_limits(port: Port) -> tuple[int, int]:
    """(max, min) position limit read over the bus."""
    port.write(packet2(SERVO, READ, bytes([LIMITS_ADDRESS, 0, LIMITS_SIZE, 0])))
    status = port.status2(timeout=2.0)
    check(status is not None and status.error == 0 and len(status.params) == LIMITS_SIZE,
          f"bad reply to a Read of the position limits: {status}")
    return (int.from_bytes(status.params[:4], "little"),
            int.from_bytes(status.params[4:], "little"))


def new_limits(rng: random.Random, old: tuple[int, int]) -> tuple[int, int]:
    """A (max, min) pair in range that differs from `old` in both items."""
    while True:
        pair = (rng.randint(0, 4095), rng.randint(0, 4095))
        if pair[0] != old[0] and pair[1] != old[1]:
            return pair


def acknowledged_before(port: Port, deadline: float) -> bool:
    """Waits until `deadline` (time.monotonic()) and says whether the Write's status came
    before it. Reads the descriptor directly: the wait must end at the kill moment exactly."""
    received = b""
    acknowledged = False
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return acknowledged
        if acknowledged or not select.select([port.fd], [], [], left)[0]:
            time.sleep(max(0.0, deadline - time.monotonic()))
            return acknowledged
        received += os.read(port.fd, 256)
        status, _ = frame_status2(received)
        if status is not None:
            check(status.id == SERVO and status.error == 0,
                  f"the Write of the limits was refused: {status}")
            acknowledged = True


def one_round(directory: str, state: str, rng: random.Random, window_s: float,
              old: tuple[int, int]) -> tuple[tuple[int, int], tuple[int, int], bool]:
    """Starts the daemon on `state`, writes new limits and kills it at a random moment.
    Returns (the pair written, the pair in the file after the kill, acknowledged)."""
    try:
        daemon = start_daemon(directory, state)
    except DaemonError as error:
        raise Failure(f"the daemon did not start with the state file left by the last kill: "
                      f"{error}") from error
    try:
        with Port(os.path.join(directory, "dxl0")) as port:
            held = read_limits(port)
            check(held == old, f"the servo holds limits {held}, the state file {old}")
            new = new_limits(rng, old)
            kill_at = time.monotonic() + rng.uniform(0.0, window_s)
            port.write(packet2(SERVO, WRITE, bytes([LIMITS_ADDRESS, 0]) + limits_bytes(new)))
            acked = acknowledged_before(port, kill_at)
            daemon.proc.send_signal(signal.SIGKILL)
            daemon.proc.wait()
    finally:
        daemon.stop()
    return new, limits_in_file(state), acked


def main() -> None:
    options = parser(__doc__.split("\n\n")[0])
    options.add_argument("--kills", type=int, help="rounds (default 1000, --quick 40)")
    options.add_argument("--window-ms", type=float, default=6.0,
                         help="the kill comes 0 to this many ms after the Write (default 6)")
    args = options.parse_args()
    rounds = args.kills or (40 if args.quick else 1000)
    rng = random.Random(args.seed)
    counts = {"old": 0, "new": 0, "new_unacked": 0}
    leftover_temp_files = 0
    most_temp_files = 0
    seen_temps: set[str] = set()
    directory = tempfile.mkdtemp(prefix="dxlemu-state-kill-")
    state = os.path.join(directory, "state.json")
    start = time.monotonic()
    try:
        current = INITIAL
        for index in range(rounds):
            new, saved, acked = one_round(directory, state, rng, args.window_ms / 1e3, current)
            check(saved in (current, new),
                  f"round {index}: the state file holds limits {saved}; before the kill it held "
                  f"{current} and the Write was of {new}")
            kept_new = saved == new
            check(kept_new or not acked,
                  f"round {index}: the Write of {new} was acknowledged on the bus before the "
                  f"kill, but the state file still holds {saved}")
            counts["new" if kept_new else "old"] += 1
            counts["new_unacked"] += kept_new and not acked
            current = saved
            # A killed daemon cannot remove the temporary file it was writing; the next
            # daemon's first save removes it (io/atomic_file.cpp).
            temps = glob.glob(state + ".tmp.*")
            most_temp_files = max(most_temp_files, len(temps))
            leftover_temp_files += len(set(temps) - seen_temps)
            seen_temps |= set(temps)
        # The last file loads too; a last Write saves it, which removes the killed daemons'
        # temporary files, and a clean stop keeps it.
        daemon = start_daemon(directory, state)
        with Port(os.path.join(directory, "dxl0")) as port:
            check(read_limits(port) == current, "the last state file did not restore the limits")
            current = new_limits(rng, current)
            port.write(packet2(SERVO, WRITE, bytes([LIMITS_ADDRESS, 0]) + limits_bytes(current)))
            check(acknowledged_before(port, time.monotonic() + 2.0), "the last Write got no status")
        code = daemon.stop()
        check(code == 0, f"the daemon did not stop cleanly: exit status {code}")
        check(limits_in_file(state) == current, "the last Write is not in the state file")
        remaining = glob.glob(state + ".tmp.*")
        check(not remaining, f"temporary files left after the last save: {remaining}")
    finally:
        shutil.rmtree(directory, ignore_errors=True)
    elapsed = time.monotonic() - start
    summary("state_kill", [
        ("rounds", f"{rounds} kill -9 in {elapsed:.1f} s, kill 0 ~ {args.window_ms:g} ms after "
                   "the Write"),
        ("file loaded and daemon started", f"{rounds + 1} of {rounds + 1}"),
        ("file held the old limits", f"{counts['old']} (all before the Write was acknowledged)"),
        ("file held the new limits", f"{counts['new']} (of which before the reply reached the "
                                     f"client: {counts['new_unacked']})"),
        ("file held anything else", "0"),
        ("temporary files left by kills", f"{leftover_temp_files}, at most {most_temp_files} "
                                          "at a time; none after the last save"),
    ])


if __name__ == "__main__":
    run(main)
