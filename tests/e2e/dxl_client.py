"""The end-to-end tests' DYNAMIXEL client and daemon handle, from the repository's Python
package (python/dxlemu, standard library only).

The package's codec is written independently of the C++ one, from ../shared/reference/
protocol1.md, protocol2.md and protocol2-crc.md. This module only adds `python/` to sys.path,
re-exports the names the tests use, and keeps `Daemon`, the tests' raw handle on
`dxlemu run ARGS` (arguments as given, one readiness line read, stdout and stderr left to the
test), `dxlemu_command`, the argument list of any other dxlemu run, and two ways of waiting on
what the daemon reports rather than on the wall clock (`heard`, `assert_unanswered`).

Both honour $DXLEMU_WRAPPER (scripts/memcheck.sh runs every dxlemu under valgrind that way),
and a `Daemon` $DXLEMU_CHECK_EXIT and $DXLEMU_TIMEOUT_SCALE too (python/dxlemu/daemon.py).
"""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from dxlemu import modbus  # noqa: E402
from dxlemu.codec import crc16, packet1, packet2, stuff, unstuff  # noqa: E402
from dxlemu.control import Control, ControlError  # noqa: E402
from dxlemu.daemon import DaemonError, DaemonProcess, timeout_scale, wrapper_command  # noqa: E402
from dxlemu.port import BAUD_RATES as BAUD  # noqa: E402
from dxlemu.port import Port  # noqa: E402
from dxlemu.protocol import Client  # noqa: E402

__all__ = ["BAUD", "Client", "Control", "ControlError", "Daemon", "DaemonError", "DaemonProcess",
           "Port", "assert_unanswered", "crc16", "dxlemu_command", "heard", "modbus", "packet1",
           "packet2", "stuff", "timeout_scale", "unstuff"]

BINARY = os.environ.get("DXLEMU_BIN", "build/emulator/dxlemu")


def dxlemu_command(*args: str) -> list[str]:
    """`dxlemu ARGS` as an argument list for subprocess: $DXLEMU_BIN (else
    build/emulator/dxlemu, from the checkout's root) after $DXLEMU_WRAPPER's words."""
    return [*wrapper_command(), BINARY, *args]


class Daemon:
    """`dxlemu run ARGS` in the background ($DXLEMU_BIN, else as dxlemu.daemon.find_binary),
    ready once its first readiness line has been read: `ready` is that line, `proc` the
    subprocess.Popen, whose stdout (further readiness lines) and stderr are the test's to read.
    """

    def __init__(self, *args: str):
        self._process = DaemonProcess(args, drain_stderr=False)
        self.proc: subprocess.Popen = self._process.proc
        self.ready: dict = self._process.ready[0]

    def stop(self) -> int:
        """SIGTERM (SIGKILL after 5 s), then the exit status; with $DXLEMU_CHECK_EXIT=1,
        raises DaemonError unless it is 0 (or SIGKILL sent by the test)."""
        try:
            return self._process.stop()
        finally:
            self.proc.stderr.close()


def heard(control: Control, count: int, port: str = "dxl0", timeout: float = 5.0) -> dict:
    """Asks `stats` until the daemon has read `count` bytes from the client on `port` (its
    `bytes_in`), then returns that port's counters. The daemon handles what it read completely
    (framing, and under fast and manual timing every reply due at once) before it answers its
    next control request, so the counters returned include all of it: a test can tell "heard
    and not answered" from "not heard yet" without waiting on the wall clock, and knows the
    bytes are stamped before it steps a manual clock. AssertionError after `timeout` seconds."""
    deadline = time.monotonic() + timeout * timeout_scale()
    while True:
        stats = control.call("stats", port=port)[port]
        if stats["bytes_in"] >= count:
            return stats
        if time.monotonic() > deadline:
            raise AssertionError(f"the daemon read {stats['bytes_in']} of {count} bytes on "
                                 f"{port} in {timeout} s")


def assert_unanswered(control: Control, port: Port, packet: bytes, port_name: str = "dxl0") -> dict:
    """Writes `packet` and checks that the daemon read it and answered nothing: under fast and
    manual timing a reply is counted in `replies`, and written to the PTY, by the time `heard`
    returns, so an unchanged count and no byte waiting are silence, not a slow daemon. Returns
    the port's counters after. AssertionError otherwise."""
    before = control.call("stats", port=port_name)[port_name]
    port.write(packet)
    after = heard(control, before["bytes_in"] + len(packet), port_name)
    arrived = port.read(1, timeout=0.05)
    if after["replies"] != before["replies"] or arrived:
        replies = after["replies"] - before["replies"]
        raise AssertionError(f"{packet.hex(' ')} was answered ({replies} replies counted, "
                             f"{arrived.hex(' ') or 'nothing'} arrived)")
    return after
