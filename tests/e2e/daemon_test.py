"""End-to-end tests: the real dxlemu binary, driven over its pseudo-terminal (docs/testing.md).

Timing assertions use generous bounds only: these machines are shared and noisy.
"""
import os
import subprocess
import tempfile
import time
import unittest

from dxl_client import Daemon, Port, packet1, packet2

PING, READ, WRITE, SYNC_READ = 0x01, 0x02, 0x03, 0x82
XM430_W350_PING = bytes([0xFC, 0x03, 45])  # model number 1020, firmware 45 (models/xm430-w350.json)


class DaemonTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.link = os.path.join(self.dir.name, "dxl0")

    def tearDown(self):
        self.dir.cleanup()

    def start(self, *args):
        daemon = Daemon("--link", self.link, *args)
        self.addCleanup(daemon.stop)
        return daemon

    def test_readiness_line_names_the_port_the_pty_the_link_and_the_servos(self):
        ready = self.start().ready
        self.assertEqual(ready["event"], "ready")
        self.assertEqual(ready["port"], "dxl0")
        self.assertTrue(ready["pty"].startswith("/dev/pts/"))
        self.assertEqual(ready["link"], self.link)
        self.assertEqual(os.path.realpath(self.link), ready["pty"])
        self.assertEqual(ready["servos"], [{"id": i, "model": "xm430-w350"} for i in (1, 2, 3)])

    def test_ping_read_and_write_in_protocol_2(self):
        self.start()
        port = Port(self.link)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2(), (1, 0, XM430_W350_PING))
        port.write(packet2(2, WRITE, bytes([116, 0, 0x00, 0x02, 0x00, 0x00])))  # Goal Position 512
        self.assertEqual(port.status2(), (2, 0, b""))
        port.write(packet2(2, READ, bytes([116, 0, 4, 0])))
        self.assertEqual(port.status2(), (2, 0, bytes([0x00, 0x02, 0x00, 0x00])))
        port.close()

    def test_protocol_1_servo_at_1_mbps_on_a_mixed_bus(self):
        self.start("--servo", "xm430-w350:1", "--servo", "ax-12a:5")
        port = Port(self.link, 1000000)  # AX-12A factory rate; the XM430 hears noise
        port.write(packet1(5, PING))
        self.assertEqual(port.status1(), (5, 0, b""))
        port.write(packet1(5, READ, bytes([0, 2])))  # Model Number
        self.assertEqual(port.status1(), (5, 0, bytes([12, 0])))
        port.write(packet2(1, PING))
        self.assertIsNone(port.status2(timeout=0.2))
        port.close()

    def test_broadcast_ping_and_sync_read_answer_in_order(self):
        self.start()
        port = Port(self.link)
        port.write(packet2(0xFE, PING))
        self.assertEqual([port.status2()[0] for _ in range(3)], [1, 2, 3])
        port.write(packet2(0xFE, SYNC_READ, bytes([7, 0, 1, 0, 3, 1, 2])))  # ID, in order 3 1 2
        self.assertEqual([port.status2() for _ in range(3)],
                         [(3, 0, b"\x03"), (1, 0, b"\x01"), (2, 0, b"\x02")])
        port.close()

    def test_a_packet_split_across_writes_is_answered(self):
        # Protocol 2.0 allows 1.5 ms between bytes, too little to sleep reliably on a busy
        # machine: the halves go back to back. Protocol 1.0 allows 100 ms: 20 ms apart.
        self.start("--servo", "xm430-w350:3", "--servo", "ax-12a:5")
        port = Port(self.link)
        ping = packet2(3, PING)
        port.write(ping[:4])
        port.write(ping[4:])
        self.assertEqual(port.status2(), (3, 0, XM430_W350_PING))
        port.set_baud(1000000)
        ping = packet1(5, PING)
        port.write(ping[:3])
        time.sleep(0.02)
        port.write(ping[3:])
        self.assertEqual(port.status1(), (5, 0, b""))
        port.close()

    def test_a_client_at_another_baud_rate_gets_no_answer(self):
        self.start()
        port = Port(self.link, 115200)
        port.write(packet2(1, PING))
        self.assertIsNone(port.status2(timeout=0.2))
        port.set_baud(57600)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2(), (1, 0, XM430_W350_PING))
        port.close()

    def test_reply_time_is_at_least_the_modelled_time(self):
        self.start()
        port = Port(self.link)
        start = time.monotonic()
        port.write(packet2(1, PING))
        self.assertIsNotNone(port.status2())
        elapsed = time.monotonic() - start
        # 10 + 14 bytes at 57600 baud, 50 us processing, 500 us Return Delay Time: 4.72 ms.
        self.assertGreaterEqual(elapsed, 0.0045)
        self.assertLess(elapsed, 0.5)
        port.close()

    def test_a_thousand_close_and_reopen_cycles_each_get_an_answer(self):
        self.start()
        for _ in range(1000):
            port = Port(self.link)
            port.write(packet2(1, PING))
            self.assertEqual(port.status2()[0], 1)
            port.close()

    def test_baud_option_moves_every_servo_to_that_rate(self):
        self.start("--baud", "1000000")
        port = Port(self.link, 1000000)
        port.write(packet2(2, PING))
        self.assertEqual(port.status2(), (2, 0, XM430_W350_PING))
        port.write(packet2(2, READ, bytes([8, 0, 1, 0])))  # Baud Rate item: index 3 is 1 Mbps
        self.assertEqual(port.status2(), (2, 0, b"\x03"))
        port.close()

    def test_protocol_option_switches_x_servos_to_protocol_1(self):
        self.start("--protocol", "1")
        port = Port(self.link)
        port.write(packet1(1, PING))
        self.assertEqual(port.status1(), (1, 0, b""))
        port.write(packet2(1, PING))
        self.assertIsNone(port.status2(timeout=0.2))
        port.close()

    def test_sigterm_stops_cleanly_and_removes_the_link(self):
        daemon = Daemon("--link", self.link)
        self.assertTrue(os.path.islink(self.link))
        self.assertEqual(daemon.stop(), 0)
        self.assertFalse(os.path.lexists(self.link))

    def test_bad_servo_options_are_refused_with_exit_code_2(self):
        binary = os.environ.get("DXLEMU_BIN", "build/emulator/dxlemu")
        for args, message in [(["--servo", "xm999:1"], 'unknown model "xm999"'),
                              (["--servo", "xm430-w350:x"], "the ID part must be a number"),
                              (["--servo", "xm430-w350:5-2"], "IDs must lie in 0 ~ 252"),
                              (["--servo", "ax-12a:1", "--baud", "4500000"],
                               "ax-12a cannot do it (it offers 1000000"),
                              (["--servo", "xl-320:1", "--protocol", "1"],
                               "xl-320 cannot speak it")]:
            result = subprocess.run([binary, "run", "--link", self.link, *args],
                                    capture_output=True, text=True, timeout=10)
            self.assertEqual(result.returncode, 2, args)
            self.assertIn(message, result.stderr)
            self.assertFalse(os.path.lexists(self.link))


if __name__ == "__main__":
    unittest.main()
