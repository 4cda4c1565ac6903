"""End-to-end: replies a client never reads do not pile up in the daemon.

Found while writing scripts/reliability: a client that sent instructions and never read the
replies (a script that only writes, ignoring Status packets) made the daemon queue every reply
once the PTY was full, without limit (200,000 Pings: 2.8 MB queued, RSS up 11 MB), and hand the
stale replies over whenever the client read again, even after it flushed its input. The daemon
now drops replies while 64 KiB wait for room, as a serial adapter's full receive buffer does,
and counts them in `stats` as `unread_drops`.

The client writes its packets without waiting, so the daemon reads several at once and, as on a
real line, only the last of those gets its reply (docs/bus.md "Collisions"). The packets are
Reads of 512 bytes, so the replies that remain still fill the 64 KiB; every packet is accounted
for as a reply handed over, a reply dropped unread, or a collision.

A dropped reply is still traced (docs/trace.md): it was on the line, only the client's adapter
lost it. That test writes each packet only once the daemon has read the one before (its
`bytes_in`), so under manual timing, where a reply is sent as soon as its instruction is
complete, no packet collides and every one earns a reply: each is in the trace, handed over or
dropped.

Both run under manual timing: replies go out at once and none is dropped as late, however busy
the machine, so every reply is one the PTY's buffer and the daemon's queue account for.

Run by ctest as reliability.unread_replies_do_not_pile_up (DXLEMU_BIN set).
"""
from __future__ import annotations

import json
import sys
import tempfile
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from dxlemu import Emulator  # noqa: E402
from dxlemu.protocol import PING, READ, Port, packet2  # noqa: E402

READS = 200_000
READ_SIZE = 512
DAEMON_QUEUE_LIMIT = 64 * 1024


def rss_kib(pid: int) -> int:
    with open(f"/proc/{pid}/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))


class UnreadRepliesDoNotPileUp(unittest.TestCase):
    def test_a_client_that_never_reads(self):
        with Emulator(timing="manual") as emulator:
            pid = emulator.process.proc.pid
            with Port(emulator.link) as port:
                port.write(packet2(1, PING))
                self.assertIsNotNone(port.status2(timeout=2.0))
                rss_before = rss_kib(pid)
                read = packet2(1, READ, bytes([0, 0, READ_SIZE & 0xFF, READ_SIZE >> 8]))
                for _ in range(READS):
                    port.write(read)
                deadline = time.monotonic() + 10
                sent = len(packet2(1, PING)) + READS * len(read)
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
                stats = emulator.control.stats()["dxl0"]
                self.assertGreater(stats["unread_drops"], 0, stats)
                self.assertEqual(stats["replies"] + stats["unread_drops"] + stats["collisions"],
                                 stats["frames"], stats)
                port.write(packet2(2, PING))
                self.assertEqual(port.status2(timeout=2.0).id, 2)
            self.assertEqual(emulator.stop(), 0)

    def test_replies_dropped_unread_are_traced(self):
        reads = 2_000  # about 1 MB of replies: well past the PTY's buffer and the daemon's 64 KiB
        with tempfile.TemporaryDirectory() as tmp:
            trace = Path(tmp) / "trace.jsonl"
            with Emulator(timing="manual", trace=trace) as emulator:
                control = emulator.control
                with Port(emulator.link) as port:
                    read = packet2(1, READ, bytes([0, 0, READ_SIZE & 0xFF, READ_SIZE >> 8]))
                    for sent in range(1, reads + 1):
                        port.write(read)
                        # Read by the daemon, and replied to, before the next packet is written:
                        # no two packets in one read, so none collides with a reply still due.
                        deadline = time.monotonic() + 10
                        while control.stats()["dxl0"]["bytes_in"] < sent * len(read):
                            self.assertLess(time.monotonic(), deadline,
                                            f"the daemon did not read packet {sent}")
                    stats = control.stats()["dxl0"]
                self.assertEqual(emulator.stop(), 0)
            lines = [json.loads(line) for line in trace.read_text().splitlines()]
        outs = [line for line in lines if line["dir"] == "out"]
        self.assertEqual((stats["bytes_in"], stats["frames"], stats["collisions"]),
                         (reads * len(read), reads, 0), stats)
        self.assertGreater(stats["unread_drops"], 0, stats)
        self.assertGreater(stats["replies"], 0, stats)
        self.assertEqual(stats["replies"] + stats["unread_drops"], reads, stats)
        self.assertEqual(len(outs), reads, stats)  # every reply traced, dropped ones too
        self.assertTrue(all(line["packet"].startswith("id=1 error=0x00") for line in outs))


if __name__ == "__main__":
    unittest.main()
