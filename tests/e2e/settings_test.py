"""End-to-end: a reading computed from a setting follows the setting on the very next read, over a
real PTY, in every timing mode (docs/motion.md "Settings the readings follow at once").

LeRobot calibrates a Koch arm (XL430-W250 and XL330-M288) by writing Homing_Offset and reading
Present_Position right after; Drive_Mode's reverse bit is read back the same way. The servos
rest with torque off, so Present Position = direction x shaft + Homing Offset exactly, whatever
the wall clock did between the two packets.
"""
import os
import random
import tempfile
import unittest

from dxl_client import Daemon, Port, packet2

READ, WRITE = 0x02, 0x03
# X series control table (models/xl330-m288.json, models/xl430-w250.json).
DRIVE_MODE, HOMING_OFFSET, PRESENT_POSITION = 10, 20, 132
REVERSE = 0x01
POWER_ON_POSITION = 2048  # the shaft where the model file puts it at power-on
TRIES = 40


class SettingsTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "dxl0")

    def bus(self, timing):
        # Each timing mode is the subject, not the wall clock: a reply the loaded machine made
        # late under realtime or fast timing is still sent, not dropped (docs/timing.md).
        late = ["--late-reply-limit-ms", "0"] if timing != "manual" else []
        daemon = Daemon("--link", self.link, "--timing", timing, *late,
                        "--servo", "xl430-w250:1", "--servo", "xl330-m288:2")
        self.addCleanup(daemon.stop)
        port = Port(self.link)
        self.addCleanup(port.close)
        return port

    def write(self, port, servo, address, value, size):
        port.write(packet2(servo, WRITE, bytes([address, 0]) + value.to_bytes(size, "little", signed=True)))
        self.assertEqual(port.status2(), (servo, 0, b""))

    def read(self, port, servo, address, size):
        port.write(packet2(servo, READ, bytes([address, 0, size, 0])))
        ident, error, data = port.status2()
        self.assertEqual((ident, error), (servo, 0))
        return int.from_bytes(data, "little", signed=True)

    def calibrate(self, timing):
        """TRIES rounds of write-then-read at once; returns the reads that missed."""
        port = self.bus(timing)
        rng = random.Random(timing)
        wrong = []
        for attempt in range(TRIES):
            servo = 1 + attempt % 2
            homing = rng.randint(-2047, 2047)
            self.write(port, servo, HOMING_OFFSET, homing, 4)
            got = self.read(port, servo, PRESENT_POSITION, 4)
            if got != POWER_ON_POSITION + homing:
                wrong.append(("homing", servo, homing, got))
            reverse = attempt % 3 == 0
            self.write(port, servo, DRIVE_MODE, REVERSE if reverse else 0, 1)
            got = self.read(port, servo, PRESENT_POSITION, 4)
            expected = (-POWER_ON_POSITION if reverse else POWER_ON_POSITION) + homing
            if got != expected:
                wrong.append(("drive mode", servo, homing, got))
            self.write(port, servo, DRIVE_MODE, 0, 1)
        return wrong

    def test_fast_timing_reads_the_new_homing_offset_and_direction_at_once(self):
        self.assertEqual(self.calibrate("fast"), [])

    def test_realtime_timing_reads_the_new_homing_offset_and_direction_at_once(self):
        self.assertEqual(self.calibrate("realtime"), [])

    def test_manual_timing_reads_them_at_once_although_no_tick_ever_runs(self):
        self.assertEqual(self.calibrate("manual"), [])


if __name__ == "__main__":
    unittest.main()
