"""End-to-end: replies through an emulated USB serial adapter (`--adapter-latency-ms`,
docs/timing.md "USB adapter latency"), over a real PTY.

The adapter's latency timer restarts with every USB packet, so a client that writes as soon as a
reply came waits one whole period for the next. The wall clock is the subject, except under
manual timing, where the adapter's timer is checked on the stepped clock. Only lower bounds on
the wall clock are asserted, plus generous upper ones for the runs without an adapter: these
machines are shared and noisy. A reply the machine made late is still sent (no
--late-reply-limit-ms): dropped, it would fail a ping loop for the machine's sake.
"""
import json
import os
import subprocess
import tempfile
import time
import unittest

from dxl_client import Control, Daemon, Port, dxlemu_command, heard, packet2, timeout_scale

PING = 0x01
BROADCAST = 0xFE
PING_STATUS = 14  # bytes of an X servo's Ping status
LOOPS = 20
LATENCY_S = 0.016


class AdapterTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def start(self, *args):
        daemon = Daemon(*args, "--late-reply-limit-ms", "0")
        self.addCleanup(daemon.stop)
        control = Control(daemon.ready["control"])
        self.addCleanup(control.close)
        return daemon, control

    def open(self, path):
        port = Port(path)
        self.addCleanup(port.close)
        return port

    def ping_loop(self, port, servo=1):
        """Seconds from the first ping's write to the last status, LOOPS pings back to back."""
        began = time.monotonic()
        for _ in range(LOOPS):
            port.write(packet2(servo, PING))
            status = port.status2(timeout=2.0)
            self.assertIsNotNone(status)
            self.assertEqual(status[:2], (servo, 0))
        return time.monotonic() - began

    def adapter_of(self, control, name="dxl0"):
        return next(p for p in control.list()["ports"] if p["name"] == name)["adapter"]

    def test_back_to_back_pings_come_one_latency_period_apart(self):
        link = os.path.join(self.dir.name, "dxl0")
        _, control = self.start("--link", link, "--servo", "xm430-w350:1",
                                "--adapter-latency-ms", "16")
        self.assertEqual(self.adapter_of(control),
                         {"latency_ms": 16, "chip": "ft232h", "packet_data_bytes": 510,
                          "unread_drops": 0})
        elapsed = self.ping_loop(self.open(link))
        # Each reply waits for the expiry one period after the packet of the one before.
        self.assertGreaterEqual(elapsed, (LOOPS - 1) * LATENCY_S)

    def test_without_an_adapter_the_same_pings_take_a_fraction_of_that(self):
        link = os.path.join(self.dir.name, "dxl0")
        _, control = self.start("--link", link, "--servo", "xm430-w350:1")
        self.assertEqual(self.adapter_of(control), {"latency_ms": 0})
        elapsed = self.ping_loop(self.open(link))
        # 20 x ~3.2 ms modelled at 57600 bit/s; the bound leaves room for a loaded machine.
        self.assertLess(elapsed, (LOOPS - 1) * LATENCY_S * timeout_scale())

    def test_a_config_port_sets_its_own_latency_over_the_command_line(self):
        slow, direct = (os.path.join(self.dir.name, name) for name in ("slow", "direct"))
        config = os.path.join(self.dir.name, "bus.json")
        with open(config, "w") as f:
            json.dump({"ports": [
                {"name": "slow", "link": slow, "servos": [{"model": "xm430-w350", "id": 1}]},
                {"name": "direct", "link": direct, "adapter_latency_ms": 0,
                 "servos": [{"model": "xm430-w350", "id": 1}]},
            ]}, f)
        _, control = self.start("--config", config, "--adapter-latency-ms", "16",
                                "--adapter-chip", "ft232r")
        self.assertEqual(self.adapter_of(control, "slow")["latency_ms"], 16)
        self.assertEqual(self.adapter_of(control, "slow")["packet_data_bytes"], 62)
        self.assertEqual(self.adapter_of(control, "direct"), {"latency_ms": 0})
        self.assertGreaterEqual(self.ping_loop(self.open(slow)), (LOOPS - 1) * LATENCY_S)
        self.assertLess(self.ping_loop(self.open(direct)), (LOOPS - 1) * LATENCY_S * timeout_scale())

    def test_under_manual_timing_replies_wait_for_the_clock_and_come_in_usb_packets(self):
        link = os.path.join(self.dir.name, "dxl0")
        _, control = self.start("--link", link, "--servo", "xm430-w350:1-6", "--timing", "manual",
                                "--adapter-latency-ms", "16", "--adapter-chip", "ft232r")
        port = self.open(link)
        port.write(packet2(1, PING))
        heard(control, len(packet2(1, PING)))  # and, without an adapter, answered at once
        self.assertEqual(port.read(PING_STATUS, timeout=0.3), b"")
        control.clock_step(ms=15)
        self.assertEqual(port.read(PING_STATUS, timeout=0.3), b"")
        control.clock_step(ms=1)  # the timer, running since the start, expires at 16 ms
        self.assertEqual(len(port.read(PING_STATUS, timeout=2.0)), PING_STATUS)
        # Six statuses, 84 bytes: the first 62 fill a full-speed chip's packet at once, the
        # other 22 wait for the timer, restarted by that packet.
        port.write(packet2(BROADCAST, PING))
        heard(control, 2 * len(packet2(1, PING)))
        self.assertEqual(len(port.read(62, timeout=2.0)), 62)
        self.assertEqual(port.read(1, timeout=0.3), b"")
        control.clock_step(ms=16)
        self.assertEqual(len(port.read(6 * PING_STATUS - 62, timeout=2.0)), 6 * PING_STATUS - 62)

    def test_under_fast_timing_there_is_no_adapter(self):
        link = os.path.join(self.dir.name, "dxl0")
        _, control = self.start("--link", link, "--servo", "xm430-w350:1", "--timing", "fast",
                                "--adapter-latency-ms", "16")
        self.assertEqual(self.adapter_of(control), {"latency_ms": 0})
        self.assertLess(self.ping_loop(self.open(link)), (LOOPS - 1) * LATENCY_S * timeout_scale())

    def test_a_latency_beyond_255_ms_or_an_unknown_chip_is_refused(self):
        for args, named in ((("--adapter-latency-ms", "256"), "--adapter-latency-ms"),
                            (("--adapter-chip", "ch340"), 'unknown chip "ch340"')):
            result = subprocess.run(dxlemu_command("run", *args), capture_output=True, text=True,
                                    timeout=30 * timeout_scale())
            self.assertEqual(result.returncode, 2, result.stderr)
            self.assertIn(named, result.stderr)


if __name__ == "__main__":
    unittest.main()
