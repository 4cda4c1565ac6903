"""End-to-end: the real dxlemu binary driven the way DynamixelSDK's Python package drives a port.

sdk_client.py re-implements the SDK over pyserial (Debian's python3-serial), with the SDK's
timeouts, polling and packet parsing; these tests make the calls an SDK user would make
(openPort, setBaudRate, ping, broadcastPing, readNByteTxRx, writeNByteTxRx, GroupSyncRead) and
expect what real servos give. The daemon runs under manual timing, whose replies go out at once
and are never dropped as late, unless the test is about when replies come (realtime's modelled
time, fast timing's throughput); the SDK's own timeouts still run on the wall clock, as they do
against hardware. Timing assertions use generous bounds only: these machines are shared and
noisy. Run by ctest as e2e.sdk_client, which fails without pyserial.
"""
import os
import sys
import tempfile
import time
import unittest

try:
    import sdk_client as sdk
except ImportError as missing:
    sys.exit(f"sdk_test: {missing} (pyserial: Debian package python3-serial)")

from dxl_client import Control, Daemon, heard, packet2, timeout_scale

XM430_W350, AX_12A, FIRMWARE = 1020, 12, 45  # models/xm430-w350.json, models/ax-12a.json
# XM430 control table (protocol 2.0)
ID, BAUD_RATE, HOMING_OFFSET, MAX_POSITION_LIMIT = 7, 8, 20, 48
LED, GOAL_POSITION, PRESENT_POSITION = 65, 116, 132
# AX-12A control table (protocol 1.0)
AX_MODEL_NUMBER, AX_LED = 0, 25


def sdk_timeout_s(port, packet_length):
    """The SDK's setPacketTimeout(packet_length), in seconds."""
    return (port.tx_time_per_byte * packet_length + sdk.LATENCY_TIMER * 2.0 + 2.0) / 1000.0


class SdkClientTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "dxl0")

    def start(self, *args):
        daemon = Daemon("--link", self.link, *args)
        self.addCleanup(daemon.stop)
        return daemon

    def start_manual(self, *args):
        return self.start("--timing", "manual", *args)

    def open(self, baud):
        """As the SDK's examples do: openPort() (at the SDK's default 1 Mbps), then setBaudRate."""
        port = sdk.PortHandler(self.link)
        self.assertTrue(port.openPort())
        self.addCleanup(port.closePort)
        self.assertTrue(port.setBaudRate(baud))
        return port

    def test_a_scan_of_every_id_finds_the_three_servos_of_the_default_bus(self):
        self.start_manual()
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        found, others = {}, set()
        start = time.monotonic()
        for dxl_id in range(0, 253):
            model, result, error = ph.ping(port, dxl_id)
            if result == sdk.COMM_SUCCESS:
                self.assertEqual(error, 0)
                found[dxl_id] = model
            else:
                others.add(result)
        elapsed = time.monotonic() - start
        self.assertEqual(found, {1: XM430_W350, 2: XM430_W350, 3: XM430_W350})
        self.assertEqual(others, {sdk.COMM_RX_TIMEOUT})
        # Each absent ID costs the SDK its whole ping timeout (11 bytes + 34 ms = 35.9 ms).
        self.assertGreater(elapsed, 250 * sdk_timeout_s(port, 11) * 0.95)
        self.assertLess(elapsed, 60)

    def test_a_ping_answers_after_the_modelled_time_and_within_the_sdk_timeout(self):
        self.start()
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        for _ in range(20):
            start = time.monotonic()
            self.assertEqual(ph.ping(port, 2), (XM430_W350, sdk.COMM_SUCCESS, 0))
            elapsed = time.monotonic() - start
            # 10 + 14 bytes at 57600 baud, 50 us processing, 500 us Return Delay Time: 4.72 ms;
            # success itself means it came before the SDK's 35.9 ms timeout.
            self.assertGreaterEqual(elapsed, 0.0045)

    def test_broadcast_ping_returns_the_three_servos_with_model_and_firmware(self):
        self.start_manual()
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        start = time.monotonic()
        data, result = ph.broadcastPing(port)
        elapsed = time.monotonic() - start
        self.assertEqual(result, sdk.COMM_SUCCESS)
        self.assertEqual(data, {i: [XM430_W350, FIRMWARE] for i in (1, 2, 3)})
        # The SDK always waits its whole timeout: 14 * 252 bytes + 3 ms * 252 + 16 ms = 1.38 s.
        wait = (14 * 252 * port.tx_time_per_byte + 3.0 * 252 + 16.0) / 1000.0
        self.assertGreater(elapsed, wait * 0.95)
        self.assertLess(elapsed, wait + 10)

    def check_reads_and_writes(self, port, ph):
        self.assertEqual(ph.write4ByteTxRx(port, 1, GOAL_POSITION, 3000), (sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read4ByteTxRx(port, 1, GOAL_POSITION), (3000, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read4ByteTxRx(port, 2, GOAL_POSITION), (2048, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read4ByteTxRx(port, 3, PRESENT_POSITION),
                         (2048, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.write1ByteTxRx(port, 3, LED, 1), (sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read1ByteTxRx(port, 3, LED), (1, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read1ByteTxRx(port, 2, LED), (0, sdk.COMM_SUCCESS, 0))
        # -131073 is FF FF FD FF on the wire. The SDK sends it unstuffed (its txPacket drops
        # addStuffing's result), which dxlemu accepts (docs/wire.md "Lenient unstuffing"); the
        # status carries it stuffed and the SDK's removeStuffing takes the FD out again.
        self.assertEqual(ph.write4ByteTxRx(port, 2, HOMING_OFFSET, -131073 & 0xFFFFFFFF),
                         (sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read4ByteTxRx(port, 2, HOMING_OFFSET),
                         (0xFFFDFFFF, sdk.COMM_SUCCESS, 0))
        # Past Max Position Limit: refused with Data Limit Error (6) in the status's error byte.
        self.assertEqual(ph.write4ByteTxRx(port, 1, MAX_POSITION_LIMIT, 3500),
                         (sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.write4ByteTxRx(port, 1, GOAL_POSITION, 4000), (sdk.COMM_SUCCESS, 6))
        self.assertEqual(ph.read4ByteTxRx(port, 1, GOAL_POSITION), (3000, sdk.COMM_SUCCESS, 0))

    def test_write_and_read_goal_position_and_led(self):
        self.start_manual()
        port = self.open(57600)
        self.check_reads_and_writes(port, sdk.Protocol2PacketHandler())

    def test_write_and_read_with_fast_timing(self):
        self.start("--timing", "fast")
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        self.check_reads_and_writes(port, ph)
        data, result = ph.broadcastPing(port)
        self.assertEqual((data, result), ({i: [XM430_W350, FIRMWARE] for i in (1, 2, 3)},
                                          sdk.COMM_SUCCESS))
        # Replies come at once: 100 reads take less than half of 100 modelled round trips
        # (14 + 12 bytes at 57600 baud, 50 us processing, 500 us Return Delay Time: 5.1 ms).
        start = time.monotonic()
        for _ in range(100):
            self.assertEqual(ph.read1ByteTxRx(port, 3, ID), (3, sdk.COMM_SUCCESS, 0))
        round_trip = (26 * port.tx_time_per_byte + 0.55) / 1000.0
        # A sanitized daemon is slower (scripts/test.sh sets DXLEMU_TIMEOUT_SCALE for it).
        self.assertLess(time.monotonic() - start, 100 * round_trip / 2 * timeout_scale())

    def test_broadcast_baud_rate_write_then_the_sdk_follows_at_1_mbps(self):
        control_path = os.path.join(self.dir.name, "control.sock")
        self.start_manual("--control", control_path)
        control = Control(control_path)
        self.addCleanup(control.close)
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        # Baud Rate 3 is 1 Mbps. A broadcast write has no status: txRxPacket returns once sent.
        self.assertEqual(ph.write1ByteTxRx(port, sdk.BROADCAST_ID, BAUD_RATE, 3),
                         (sdk.COMM_SUCCESS, 0))
        # A real UART has sent the packet at 57600 before the port closes (close drains output).
        # dxlemu takes the client's rate when it reads the bytes from the PTY, so bytes it has
        # not read yet when setBaudRate reopens the port would count as sent at 1 Mbps and the
        # servos would not hear them: wait until it has read them (its bytes_in) first.
        heard(control, len(packet2(sdk.BROADCAST_ID, 0x03, bytes([BAUD_RATE, 0, 3]))))
        self.assertTrue(port.setBaudRate(1000000))
        for dxl_id in (1, 2, 3):
            self.assertEqual(ph.ping(port, dxl_id), (XM430_W350, sdk.COMM_SUCCESS, 0))
            self.assertEqual(ph.read1ByteTxRx(port, dxl_id, BAUD_RATE), (3, sdk.COMM_SUCCESS, 0))
        self.assertTrue(port.setBaudRate(57600))
        self.assertEqual(ph.ping(port, 1)[1], sdk.COMM_RX_TIMEOUT)

    def test_group_sync_read_of_present_position(self):
        self.start_manual()
        port = self.open(57600)
        ph = sdk.Protocol2PacketHandler()
        group = sdk.GroupSyncRead(port, ph, PRESENT_POSITION, 4)
        for dxl_id in (1, 2, 3):
            self.assertTrue(group.addParam(dxl_id))
        for _ in range(10):
            self.assertEqual(group.txRxPacket(), sdk.COMM_SUCCESS)
            for dxl_id in (1, 2, 3):
                self.assertTrue(group.isAvailable(dxl_id, PRESENT_POSITION, 4))
                self.assertEqual(group.getData(dxl_id, PRESENT_POSITION, 4), 2048)
        # Each ID's own data: the IDs themselves, asked for in another order.
        group = sdk.GroupSyncRead(port, ph, ID, 1)
        for dxl_id in (3, 1, 2):
            group.addParam(dxl_id)
        self.assertEqual(group.txRxPacket(), sdk.COMM_SUCCESS)
        self.assertEqual([group.getData(i, ID, 1) for i in (1, 2, 3)], [1, 2, 3])

    def test_protocol_1_ping_read_and_write_of_an_ax_12a_at_1_mbps(self):
        self.start_manual("--servo", "ax-12a:1")
        port = self.open(1000000)
        ph = sdk.Protocol1PacketHandler()
        # The SDK's 1.0 ping is a Ping, then a Read of Model Number.
        self.assertEqual(ph.ping(port, 1), (AX_12A, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.ping(port, 2)[1], sdk.COMM_RX_TIMEOUT)
        self.assertEqual(ph.read2ByteTxRx(port, 1, AX_MODEL_NUMBER), (AX_12A, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.write1ByteTxRx(port, 1, AX_LED, 1), (sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.read1ByteTxRx(port, 1, AX_LED), (1, sdk.COMM_SUCCESS, 0))
        self.assertEqual(ph.broadcastPing(port), (None, sdk.COMM_NOT_AVAILABLE))
        # Protocol 2.0 gets no answer from a 1.0-only servo.
        self.assertEqual(sdk.Protocol2PacketHandler().ping(port, 1)[1], sdk.COMM_RX_TIMEOUT)


if __name__ == "__main__":
    unittest.main()
