"""End-to-end: replies a client never reads do not pile up in the daemon.

Found while writing scripts/reliability: a client that sent instructions and never read the
replies (a script that only writes, ignoring Status packets) made the daemon queue every reply
once the PTY was full, without limit (200,000 Pings: 2.8 MB queued, RSS up 11 MB), and hand the
stale replies over whenever the client read again, even after it flushed its input. The daemon
now drops replies while 64 KiB wait for room, as a serial adapter's full receive buffer does.

Run by ctest as reliability.unread_replies_do_not_pile_up (DXLEMU_BIN set).
"""
from __future__ import annotations

import sys
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from dxlemu import Emulator  # noqa: E402
from dxlemu.protocol import PING, Port, packet2  # noqa: E402

PINGS = 200_000
PER_WRITE = 100
DAEMON_QUEUE_LIMIT = 64 * 1024


def rss_kib(pid: int) -> int:
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


class UnreadRepliesDoNotPileUp(unittest.TestCase):
    def test_a_client_that_never_reads(self):
        with Emulator(timing="fast") as emulator:
            pid = emulator.process.proc.pid
            with Port(emulator.link) as port:
                port.write(packet2(1, PING))
                self.assertIsNotNone(port.status2(timeout=2.0))
                rss_before = rss_kib(pid)
                for _ in range(PINGS // PER_WRITE):
                    port.write(packet2(1, PING) * PER_WRITE)
                deadline = time.monotonic() + 10
                sent = (PINGS + 1) * len(packet2(1, PING))
                while emulator.control.stats()["dxl0"]["bytes_in"] < sent:
                    self.assertLess(time.monotonic(), deadline, "the daemon did not read it all")
                    time.sleep(0.05)
                growth = rss_kib(pid) - rss_before
                self.assertLess(growth, 2048, f"RSS grew by {growth} KiB")
                # What the client finds once it reads: the PTY's buffer and the daemon's queue,
                # not every reply since it stopped reading.
                stale = 0
                while chunk := port.read(65536, timeout=0.3):
                    stale += len(chunk)
                self.assertLess(stale, DAEMON_QUEUE_LIMIT + 128 * 1024)
                port.write(packet2(2, PING))
                self.assertEqual(port.status2(timeout=2.0).id, 2)
            self.assertEqual(emulator.stop(), 0)


if __name__ == "__main__":
    unittest.main()
