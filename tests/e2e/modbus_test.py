"""End-to-end: DYNAMIXEL-P and the RH-P12-RN(A) gripper over Modbus RTU on a real PTY, driven by
independent Modbus masters from Debian: pymodbus (python3-pymodbus) and mbpoll (libmodbus).

`dxlemu run --servo ph54-200-s500-r:1 --protocol modbus` (docs/modbus.md): Model Number 2020 at
40001; Torque Enable and Goal Position writes move the servo and Present Position follows; a
write to a read-only register and one into half of Goal Position get exception 02; the gripper
closes; switching Protocol Type back to 2 over Modbus makes the same servo answer DynamixelSDK's
Protocol 2.0 (tests/e2e/sdk_client.py) with the table the Modbus writes left.

Every master must use 8N1 (mbpoll's default parity is even: `-P none`); a master with even parity
is not heard at all (docs/bus.md).
"""
import errno
import os
import shutil
import subprocess
import tempfile
import termios
import time
import unittest

from dxl_client import Control, Daemon, timeout_scale

try:
    from pymodbus.client import ModbusSerialClient
except ImportError as e:  # a missing tool fails loudly, never skips
    raise SystemExit(f"e2e.modbus: pymodbus is missing ({e}); Debian packages python3-pymodbus "
                     "and python3-serial-asyncio (scripts/setup.sh installs them)")
import sdk_client as sdk

MBPOLL = shutil.which("mbpoll")
if MBPOLL is None:
    raise SystemExit("e2e.modbus: mbpoll is missing (Debian package mbpoll; scripts/setup.sh)")

BAUD = 57600  # the P series' and the gripper's factory Baud Rate (index 1)
# Registers: 40001 + floor(address / 2); PDU addresses count from 0.
MODEL_NUMBER = 0          # Model Number (0)
PROTOCOL_TYPE = 13 // 2   # 40007: Secondary ID (12, N/A) low byte, Protocol Type (13) high
TORQUE_ENABLE = 512 // 2  # 40257: Torque Enable (512) low byte, LED Red (513) high
GOAL_POSITION = 564 // 2  # 40283-40284, low word first
PRESENT_POSITION = 580 // 2
ILLEGAL_DATA_ADDRESS = 2


def words(value: int) -> list[int]:
    """A signed 32-bit item as two registers, low word first."""
    unsigned = value & 0xFFFFFFFF
    return [unsigned & 0xFFFF, unsigned >> 16]


def value_of(registers: list[int]) -> int:
    unsigned = registers[0] | registers[1] << 16
    return unsigned - (1 << 32) if unsigned & 0x80000000 else unsigned


class ModbusSession(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "dxl0")

    def start(self, *servos: str, timing: str = "realtime") -> Control:
        late = ["--late-reply-limit-ms", "0"] if timing != "manual" else []
        args = ["--link", self.link, "--timing", timing, *late, "--protocol", "modbus"]
        for servo in servos:
            args += ["--servo", servo]
        daemon = Daemon(*args)
        self.addCleanup(daemon.stop)
        control = Control(daemon.ready["control"])
        self.addCleanup(control.close)
        return control

    def master(self, parity: str = "N") -> ModbusSerialClient:
        client = ModbusSerialClient(port=self.link, baudrate=BAUD, parity=parity,
                                    timeout=1.0 * timeout_scale(), retries=0)
        self.assertTrue(client.connect())
        self.addCleanup(client.close)
        return client

    def mbpoll(self, *args: str, check: bool = True) -> subprocess.CompletedProcess:
        command = [MBPOLL, "-m", "rtu", "-b", str(BAUD), "-P", "none", "-a", "1", "-1",
                   "-o", str(1.0 * timeout_scale()), *args]
        return subprocess.run(command, capture_output=True, text=True, check=check, timeout=30)

    def test_pymodbus_reads_writes_moves_and_sees_exceptions_then_sdk_takes_over(self):
        control = self.start("ph54-200-s500-r:1")
        self.assertEqual(control.call("list")["ports"]["dxl0"]["servos"][0]["protocol"], "modbus")
        client = self.master()
        model = client.read_holding_registers(MODEL_NUMBER, 1, slave=1)
        self.assertFalse(model.isError(), model)
        self.assertEqual(model.registers, [2020])

        # A read-only register and half of the 4-byte Goal Position: Illegal Data Address.
        refused = client.write_register(MODEL_NUMBER, 7, slave=1)
        self.assertTrue(refused.isError())
        self.assertEqual(refused.exception_code, ILLEGAL_DATA_ADDRESS)
        half = client.write_register(GOAL_POSITION, 1000, slave=1)
        self.assertEqual(half.exception_code, ILLEGAL_DATA_ADDRESS)

        self.assertFalse(client.write_register(TORQUE_ENABLE, 1, slave=1).isError())
        goal = 30000
        self.assertFalse(client.write_registers(GOAL_POSITION, words(goal), slave=1).isError())
        deadline = time.monotonic() + 10 * timeout_scale()
        position = None
        while time.monotonic() < deadline:
            present = client.read_holding_registers(PRESENT_POSITION, 2, slave=1)
            self.assertFalse(present.isError(), present)
            position = value_of(present.registers)
            if abs(position - goal) < 100:
                break
            time.sleep(0.05)
        self.assertLess(abs(position - goal), 100, f"Present Position stayed at {position}")

        # Back to Protocol 2.0 (Protocol Type 2 in 40007's high byte) needs the torque off.
        self.assertFalse(client.write_register(TORQUE_ENABLE, 0, slave=1).isError())
        switched = client.write_register(PROTOCOL_TYPE, 2 << 8, slave=1)
        self.assertFalse(switched.isError(), switched)
        client.close()

        port = sdk.PortHandler(self.link)
        port.baudrate = BAUD
        self.assertTrue(port.openPort())
        self.addCleanup(port.closePort)
        handler = sdk.Protocol2PacketHandler()
        model_number, result, error = handler.ping(port, 1)
        self.assertEqual((model_number, result, error), (2020, sdk.COMM_SUCCESS, 0))
        goal_read, result, _ = handler.read4ByteTxRx(port, 1, 564)
        self.assertEqual((goal_read, result), (goal, sdk.COMM_SUCCESS))

    def test_mbpoll_reads_the_model_number_and_is_refused_a_read_only_write(self):
        self.start("ph54-200-s500-r:1")
        # mbpoll counts references from 1: -r 1 is 40001.
        out = self.mbpoll("-r", "1", "-c", "1", "-t", "4", self.link).stdout
        self.assertIn("[1]: \t2020", out)
        refused = self.mbpoll("-r", "1", "-t", "4", self.link, "7", check=False)
        self.assertNotEqual(refused.returncode, 0)
        self.assertIn("Illegal data address", refused.stdout + refused.stderr)
        written = self.mbpoll("-r", str(TORQUE_ENABLE + 1), "-t", "4", self.link, "1")
        self.assertIn("Written 1 references", written.stdout)

    def test_the_gripper_closes_over_modbus(self):
        self.start("rh-p12-rna:1", timing="fast")
        client = self.master()
        self.assertEqual(client.read_holding_registers(MODEL_NUMBER, 1, slave=1).registers, [35074])
        self.assertFalse(client.write_register(TORQUE_ENABLE, 1, slave=1).isError())
        self.assertFalse(client.write_registers(GOAL_POSITION, words(700), slave=1).isError())
        deadline = time.monotonic() + 10 * timeout_scale()
        position = 0
        while time.monotonic() < deadline and abs(position - 700) > 10:
            position = value_of(client.read_holding_registers(PRESENT_POSITION, 2, slave=1).registers)
            time.sleep(0.05)
        self.assertLess(abs(position - 700), 10)

    def test_a_master_with_even_parity_is_not_heard(self):
        control = self.start("ph54-200-s500-r:1", timing="fast")
        # Some kernels (gVisor-like sandboxes) refuse parity on a PTY outright: there the master
        # cannot even ask for it, and its bytes stay 8N1. The decision itself is unit-tested
        # (tests/unit/io/tty_baud_test.cpp); here the kernel is asked first.
        fd = os.open(self.link, os.O_RDWR | os.O_NOCTTY)
        try:
            attributes = termios.tcgetattr(fd)
            attributes[2] |= termios.PARENB
            try:
                termios.tcsetattr(fd, termios.TCSANOW, attributes)
            except termios.error as e:
                self.assertEqual(e.args[0], errno.EINVAL)
                return  # the kernel keeps every PTY at no parity: nothing to tell apart
        finally:
            os.close(fd)
        client = self.master(parity="E")
        reply = client.read_holding_registers(MODEL_NUMBER, 1, slave=1)
        self.assertTrue(reply.isError())
        self.assertEqual(control.call("stats", port="dxl0")["dxl0"]["replies"], 0)

if __name__ == "__main__":
    unittest.main()
