"""End-to-end: an EEPROM write the client saw acknowledged survives an immediate kill -9.

Found by scripts/reliability/state_kill.py: under --timing fast the status of a Write went out
before the state file was rewritten (fsync, rename), so a kill -9 right after the client read
the status lost the write in most rounds. The daemon now saves before it delivers the reply.

Run by ctest as reliability.acknowledged_eeprom_write_survives_kill (DXLEMU_BIN set).
"""
from __future__ import annotations

import json
import os
import signal
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from dxlemu import DaemonProcess  # noqa: E402
from dxlemu.protocol import WRITE, Port, packet2  # noqa: E402

ROUNDS = 20
RETURN_DELAY_TIME = 9  # XM430-W350, EEPROM, 1 byte


class AcknowledgedWriteSurvivesKill(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="dxlemu-durability-")
        self.addCleanup(self.dir.cleanup)
        self.state = os.path.join(self.dir.name, "state.json")
        self.link = os.path.join(self.dir.name, "dxl0")

    def start(self, timing: str) -> DaemonProcess:
        # Each timing mode is the subject (the bug was in two of them), not the wall clock: a
        # status the loaded machine made late is still sent, not dropped (docs/timing.md).
        late = ["--late-reply-limit-ms", "0"] if timing != "manual" else []
        daemon = DaemonProcess(["--link", self.link,
                                "--control", os.path.join(self.dir.name, "control.sock"),
                                "--servo", "xm430-w350:1", "--timing", timing, *late,
                                "--state", self.state, "--log-level", "error"])
        self.addCleanup(daemon.stop)
        return daemon

    def saved_return_delay_time(self) -> int:
        with open(self.state, encoding="utf-8") as f:
            return json.load(f)["ports"]["dxl0"][0]["eeprom"]["return_delay_time"]

    def check_rounds(self, timing: str) -> None:
        for value in range(10, 10 + ROUNDS):
            daemon = self.start(timing)
            with Port(self.link) as port:
                port.write(packet2(1, WRITE, bytes([RETURN_DELAY_TIME, 0, value])))
                # A generous bound: under the sanitizers on a loaded machine a start and a fsync
                # may take seconds; what is checked is that the write survives, not how fast.
                self.assertEqual(port.status2(timeout=10.0), (1, 0, b""))
                daemon.proc.send_signal(signal.SIGKILL)  # at once, after the acknowledgement
                daemon.proc.wait()
            daemon.stop()
            self.assertEqual(self.saved_return_delay_time(), value,
                             f"{timing} timing: the acknowledged write of {value} was lost")

    def test_fast_timing(self):
        self.check_rounds("fast")

    def test_manual_timing(self):
        self.check_rounds("manual")

    def test_realtime_timing(self):
        self.check_rounds("realtime")


if __name__ == "__main__":
    unittest.main()
