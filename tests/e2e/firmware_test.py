"""End-to-end: a servo started with a firmware variant (`--servo xl330-m288@52:1`) reports that
firmware and serves that firmware's table over a real PTY, beside one of the default firmware.

The XL330/XC330 pages: "Firmware versions prior to V53 support up to 20 Indirect Address/Data
items. The address range for Indirect Address is 168 ~ 207, and for Indirect Data is 208 ~
227." A client that picks its table by the Firmware Version it reads (ROS 2's
dynamixel_hardware_interface) must find Indirect Data 1 at 208 on a servo that says 52, and at
224 on one that says 53 or later (docs/families.md "Firmware variants").
"""
import os
import subprocess
import tempfile
import unittest

from dxl_client import Daemon, Port, dxlemu_command, packet2

PING, READ, WRITE = 0x01, 0x02, 0x03
# models/xl330-m288.json: Model Number 1200, Firmware Version at 6, Present Position at 132.
MODEL_NUMBER, FIRMWARE_VERSION, PRESENT_POSITION = 1200, 6, 132
INDIRECT_ADDRESS_1 = 168
FW52_INDIRECT_DATA_1, DEFAULT_INDIRECT_DATA_1 = 208, 224
OLD, TODAY = 1, 2  # the IDs of the firmware 52 servo and of the default one


class FirmwareVariantTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.link = os.path.join(cls.dir.name, "dxl0")
        cls.daemon = Daemon("--link", cls.link, "--timing", "manual",
                            "--servo", f"xl330-m288@52:{OLD}", "--servo", f"xl330-m288:{TODAY}")
        cls.port = Port(cls.link)

    @classmethod
    def tearDownClass(cls):
        cls.port.close()
        cls.daemon.stop()
        cls.dir.cleanup()

    def ask(self, servo, instruction, params=b""):
        self.port.write(packet2(servo, instruction, params))
        ident, error, data = self.port.status2()
        self.assertEqual((ident, error), (servo, 0))
        return data

    def read(self, servo, address, size):
        return self.ask(servo, READ, address.to_bytes(2, "little") + size.to_bytes(2, "little"))

    def test_ping_and_firmware_version_report_the_selected_firmware(self):
        self.assertEqual(self.ask(OLD, PING), MODEL_NUMBER.to_bytes(2, "little") + bytes([52]))
        self.assertEqual(self.read(OLD, FIRMWARE_VERSION, 1), bytes([52]))
        today = self.read(TODAY, FIRMWARE_VERSION, 1)[0]
        self.assertGreaterEqual(today, 53)
        self.assertEqual(self.ask(TODAY, PING), MODEL_NUMBER.to_bytes(2, "little") + bytes([today]))

    def map_position(self, servo):
        """Indirect Address 1 ~ 4 = Present Position's four bytes."""
        for i in range(4):
            address = INDIRECT_ADDRESS_1 + 2 * i
            self.ask(servo, WRITE, address.to_bytes(2, "little") + (PRESENT_POSITION + i).to_bytes(2, "little"))

    def test_firmware_52_serves_indirect_data_at_208(self):
        self.map_position(OLD)
        self.assertEqual(self.read(OLD, FW52_INDIRECT_DATA_1, 4), self.read(OLD, PRESENT_POSITION, 4))
        # Indirect Address 1 reads back what was written; its factory value was its Data, 208.
        self.assertEqual(self.read(OLD, INDIRECT_ADDRESS_1, 2), PRESENT_POSITION.to_bytes(2, "little"))

    def test_the_default_firmware_serves_indirect_data_at_224(self):
        self.assertEqual(self.read(TODAY, INDIRECT_ADDRESS_1, 2), DEFAULT_INDIRECT_DATA_1.to_bytes(2, "little"))
        self.map_position(TODAY)
        self.assertEqual(self.read(TODAY, DEFAULT_INDIRECT_DATA_1, 4), self.read(TODAY, PRESENT_POSITION, 4))

    def test_an_unknown_firmware_is_refused_naming_the_known_ones(self):
        link = os.path.join(self.dir.name, "refused")
        result = subprocess.run(dxlemu_command("run", "--link", link, "--servo", "xl330-m288@51:1"),
                                capture_output=True, text=True, timeout=10)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn('xl330-m288 has no firmware "51" (known: 53, 52)', result.stderr)
        self.assertFalse(os.path.lexists(link))

    def test_models_lists_the_variant(self):
        result = subprocess.run(dxlemu_command("models", "--name", "xl330-m288"),
                                capture_output=True, text=True, timeout=10)
        self.assertEqual(result.returncode, 0, result.stderr)
        names = [line.split()[0] for line in result.stdout.splitlines()[1:]]
        self.assertEqual(names, ["xl330-m288", "xl330-m288@52"])


if __name__ == "__main__":
    unittest.main()
