"""End-to-end: a LeRobot-style session on six FEETECH STS3215 at 1 Mbit/s over a real PTY
(`dxlemu run --servo sts3215:1-6 --baud 1000000`, docs/feetech.md), and a scenario and a state
file on a FEETECH port.

It drives the bus as LeRobot's FeetechMotorsBus does through FEETECH's SDK: scan by ping
(unicast, and a broadcast ping that collides with six servos answering at once), read the model
numbers (address 3, 2 bytes = 777), calibrate (Torque 0, Lock 0, Homing_Offset, position
limits), Return delay 0, torque on (Torque 1, Lock 1), SYNC WRITE Goal_Position (42, 2 bytes),
SYNC READ Present_Position (56, 2 bytes) until every servo has arrived at its goal minus its
homing offset, then a hardware fault injected through the control API, seen in the status error
byte and in Servo status (65). Refusals (docs/feetech.md "Refusals"): a bad checksum, an unknown
instruction and a read past the table get no status, which the SDK reports as "There is no status
packet!"; LeRobot's write of 254 to read-only Maximum_Acceleration (85) is acknowledged with 0.

The daemon runs under manual timing: replies go out at once, and the moves, the fault's
detection and the scenario's timeline wait for the test to step the clock.

The FEETECH frames are built here with a small local helper (checksum = ~sum & 0xFF).
"""
import json
import os
import tempfile
import unittest

from dxl_client import Control, Daemon, Port, assert_unanswered, timeout_scale

PING, READ, WRITE, SYNC_READ, SYNC_WRITE = 0x01, 0x02, 0x03, 0x82, 0x83
BROADCAST = 0xFE
IDS = [1, 2, 3, 4, 5, 6]
# The STS memory table (feetech/sts3215.md).
MODEL_NUMBER, MIN_LIMIT, MAX_LIMIT, RETURN_DELAY = 3, 9, 11, 7
HOMING_OFFSET, TORQUE, GOAL, LOCK, PRESENT, STATUS = 31, 40, 42, 55, 56, 65
MAX_ACCELERATION = 85  # LeRobot's name; read-only in FEETECH's table
TABLE_SIZE = 87  # the STS table ends at 86
STS3215 = 777
OVERHEAT = 0x04  # Servo status bit 2 (FTServo_Python ERRBIT_OVERHEAT)
OVERLOAD = 0x20  # Servo status bit 5 (ERRBIT_OVERLOAD)
TICK_MS = 1  # the servos' motion tick, at which they detect a hardware error (docs/faults.md)
STEP_MS = 20  # how far the session steps the clock between two looks at moving servos
OVERLOAD_UNTIL_MS = 1500  # the end of the scenario's overload


def checksum(body: bytes) -> int:
    return ~sum(body) & 0xFF


def frame(ident: int, instruction: int, params: bytes = b"") -> bytes:
    """An FT-SCS instruction packet: FF FF ID LENGTH INSTRUCTION PARAMS CHECKSUM."""
    body = bytes([ident, len(params) + 2, instruction]) + params
    return b"\xff\xff" + body + bytes([checksum(body)])


def sign_magnitude(value: int, bit: int) -> int:
    """LeRobot's encode_sign_magnitude: the direction in `bit`, the magnitude below it."""
    return (abs(value) | (1 << bit)) if value < 0 else value


def word(value: int) -> bytes:
    return value.to_bytes(2, "little")


class FeetechSessionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.link = os.path.join(cls.dir.name, "ttyACM0")
        cls.daemon = Daemon("--link", cls.link, "--control", os.path.join(cls.dir.name, "ctl"),
                            "--servo", "sts3215:1-6", "--baud", "1000000", "--timing", "manual")
        cls.control = Control(cls.daemon.ready["control"])
        cls.port = Port(cls.link, 1_000_000)

    @classmethod
    def tearDownClass(cls):
        cls.port.close()
        cls.control.close()
        cls.daemon.stop()
        cls.dir.cleanup()

    def status(self, data_size: int) -> tuple[int, int, bytes]:
        """One status packet with `data_size` data bytes: (ID, error byte, data)."""
        raw = self.port.read(6 + data_size, timeout=1.0 * timeout_scale())
        self.assertEqual(len(raw), 6 + data_size, f"status cut short: {raw.hex(' ')}")
        self.assertEqual(raw[:2], b"\xff\xff")
        self.assertEqual(raw[3], data_size + 2)
        self.assertEqual(raw[-1], checksum(raw[2:-1]), f"bad checksum: {raw.hex(' ')}")
        return raw[2], raw[4], raw[5:-1]

    def ask(self, ident: int, instruction: int, params: bytes = b"", data_size: int = 0) -> tuple[int, bytes]:
        """Sends, and returns (error byte, data) of the servo's status."""
        self.port.write(frame(ident, instruction, params))
        got, error, data = self.status(data_size)
        self.assertEqual(got, ident)
        return error, data

    def write(self, ident: int, address: int, data: bytes) -> None:
        error, _ = self.ask(ident, WRITE, bytes([address]) + data)
        self.assertEqual(error, 0, f"write {address} to {ident}")

    def read(self, ident: int, address: int, size: int) -> bytes:
        error, data = self.ask(ident, READ, bytes([address, size]), size)
        self.assertEqual(error, 0)
        return data

    def sync_read(self, address: int, size: int) -> dict[int, bytes]:
        self.port.write(frame(BROADCAST, SYNC_READ, bytes([address, size, *IDS])))
        out = {}
        for ident in IDS:  # one status per ID, in the order of the request
            got, error, data = self.status(size)
            self.assertEqual((got, error), (ident, 0))
            out[got] = data
        return out

    def test_1_scan_by_ping_and_read_model_numbers(self):
        for ident in IDS:
            self.assertEqual(self.ask(ident, PING), (0, b""))
            self.assertEqual(int.from_bytes(self.read(ident, MODEL_NUMBER, 2), "little"), STS3215)
        # Nobody at ID 7: silence.
        assert_unanswered(self.control, self.port, frame(7, PING))
        # What the servo cannot say "no" to with its error byte gets no status at all.
        damaged = bytearray(frame(1, READ, bytes([PRESENT, 2])))
        damaged[-1] ^= 0x01
        assert_unanswered(self.control, self.port, bytes(damaged))
        assert_unanswered(self.control, self.port, frame(1, 0x92))
        assert_unanswered(self.control, self.port, frame(1, READ, bytes([TABLE_SIZE - 1, 2])))
        # A write it refuses is acknowledged, and changes nothing.
        limit = self.read(1, MAX_ACCELERATION, 1)
        self.write(1, MAX_ACCELERATION, bytes([254]))
        self.assertEqual(self.read(1, MAX_ACCELERATION, 1), limit)
        # Six servos answer a broadcast ping at once: one 6-byte packet whose bytes collided
        # (the wired AND of the six), with a checksum that does not match.
        self.port.write(frame(BROADCAST, PING))
        raw = self.port.read(6, timeout=1.0 * timeout_scale())
        self.assertEqual(raw, bytes([0xFF, 0xFF, 0x00, 0x02, 0x00, 0xF0]))
        self.assertNotEqual(raw[-1], checksum(raw[2:-1]))
        self.assertEqual(self.port.read(1, timeout=0.05), b"")

    def test_2_calibrate_then_move_with_sync_write_and_sync_read(self):
        homing = {ident: 100 * ident - 350 for ident in IDS}  # -250 ~ 250
        for ident in IDS:
            # LeRobot's calibration: torque off and EEPROM unlocked, then offsets and limits.
            self.write(ident, TORQUE, b"\x00")
            self.write(ident, LOCK, b"\x00")
            self.write(ident, HOMING_OFFSET, word(sign_magnitude(homing[ident], 11)))
            self.write(ident, MIN_LIMIT, word(500))
            self.write(ident, MAX_LIMIT, word(3500))
            self.write(ident, RETURN_DELAY, b"\x00")  # configure_motors()
        for ident in IDS:
            # Present_Position = Actual_Position - Homing_Offset, the shaft at 2048.
            self.assertEqual(int.from_bytes(self.read(ident, PRESENT, 2), "little"), 2048 - homing[ident])
            # enable_torque(): Torque_Enable 1, then Lock 1.
            self.write(ident, TORQUE, b"\x01")
            self.write(ident, LOCK, b"\x01")
        goals = {ident: 1000 + 300 * ident for ident in IDS}
        params = bytes([GOAL, 2]) + b"".join(bytes([ident]) + word(goals[ident]) for ident in IDS)
        assert_unanswered(self.control, self.port, frame(BROADCAST, SYNC_WRITE, params))
        for _ in range(10_000 // STEP_MS):  # 10 s of simulated time at most
            present = {i: int.from_bytes(d, "little") for i, d in self.sync_read(PRESENT, 2).items()}
            if all(abs(present[i] - goals[i]) <= 3 for i in IDS):
                break
            self.control.call("clock.step", ms=STEP_MS)
        else:
            self.fail(f"not arrived after 10 s: {present} (goals {goals})")
        # The control API sees the shaft where the offsets say.
        for ident in IDS:
            shaft = self.control.call("get", servo=ident, item="present_position")["value"]
            self.assertLessEqual(abs(shaft - goals[ident]), 3)
        # `list` names the protocol and shows FEETECH's torque switch, moving flag and status.
        servos = self.control.call("list")["ports"][0]["servos"]
        self.assertEqual([s["protocol"] for s in servos], ["feetech"] * len(IDS))
        self.assertTrue(all(s["torque"] and "moving" in s and s["servo_status"] == 0
                            for s in servos), servos)

    def test_3_a_hardware_fault_shows_in_the_status_error_byte_and_servo_status(self):
        rule = self.control.call("fault.add", rule={"action": "hardware_error", "kind": "overheating",
                                                    "match": {"servos": [3]}})
        try:
            self.control.call("clock.step", ms=TICK_MS)  # detected at the next tick
            error, data = self.ask(3, READ, bytes([STATUS, 1]), 1)
            self.assertEqual((error, data), (OVERHEAT, bytes([OVERHEAT])))
            self.assertEqual(self.ask(2, PING), (0, b""))  # the others are fine
        finally:
            self.control.call("fault.remove", rule=rule["rule"])


class FeetechScenarioAndStateTest(unittest.TestCase):
    """A scenario's timeline and a state file on a FEETECH port: an overload that a scenario
    injects for a while, and EEPROM writes that survive a restart only if made unlocked."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "ttyUSB0")
        self.state = os.path.join(self.dir.name, "state.json")

    def start(self, *extra: str) -> tuple[Daemon, Port]:
        control = os.path.join(self.dir.name, "ctl")
        daemon = Daemon("--link", self.link, "--servo", "sts3215:1-2", "--baud", "1000000",
                        "--state", self.state, "--timing", "manual", "--control", control, *extra)
        self.addCleanup(daemon.stop)
        self.control = Control(control)
        self.addCleanup(self.control.close)
        port = Port(self.link, 1_000_000)
        self.addCleanup(port.close)
        return daemon, port

    def ask(self, port: Port, ident: int, instruction: int, params: bytes, size: int = 0):
        port.write(frame(ident, instruction, params))
        raw = port.read(6 + size, timeout=1.0 * timeout_scale())
        self.assertEqual(len(raw), 6 + size, raw.hex(" "))
        self.assertEqual(raw[-1], checksum(raw[2:-1]))
        return raw[4], raw[5:-1]

    def test_a_scenario_injects_an_overload_for_its_time(self):
        scenario = os.path.join(self.dir.name, "overload.json")
        with open(scenario, "w", encoding="utf-8") as f:
            json.dump({"steps": [
                {"at_ms": 0, "cmd": "fault.add",
                 "rule": {"action": "hardware_error", "kind": "overload",
                          "match": {"servos": [2]}, "until_ms": OVERLOAD_UNTIL_MS}}]}, f)
        _, port = self.start("--scenario", scenario)
        self.control.call("clock.step", ms=TICK_MS)  # detected at the first tick
        error, data = self.ask(port, 2, READ, bytes([STATUS, 1]), 1)
        self.assertEqual((error, data), (OVERLOAD, bytes([OVERLOAD])))
        self.assertEqual(self.ask(port, 1, PING, b""), (0, b""))
        self.control.call("clock.step", ns=OVERLOAD_UNTIL_MS * 1_000_000 - 1 - TICK_MS * 1_000_000)
        self.assertEqual(self.ask(port, 2, PING, b"")[0], OVERLOAD, "gone before its until_ms")
        self.control.call("clock.step", ns=1 + TICK_MS * 1_000_000)  # and the tick that sees it go
        self.assertEqual(self.ask(port, 2, PING, b""), (0, b""), "the overload outlived its until_ms")

    def test_eeprom_written_unlocked_survives_a_restart_written_locked_does_not(self):
        daemon, port = self.start()
        self.assertEqual(self.ask(port, 1, WRITE, bytes([LOCK, 0]))[0], 0)
        self.assertEqual(self.ask(port, 1, WRITE, bytes([HOMING_OFFSET]) + word(123))[0], 0)
        # Servo 2 stays locked (Lock 1 at power-on): its write is in effect until power-off.
        self.assertEqual(self.ask(port, 2, WRITE, bytes([MIN_LIMIT]) + word(700))[0], 0)
        self.assertEqual(self.ask(port, 2, READ, bytes([MIN_LIMIT, 2]), 2)[1], word(700))
        port.close()
        self.assertEqual(daemon.stop(), 0)
        with open(self.state, encoding="utf-8") as f:
            saved = json.load(f)["ports"]["dxl0"]
        self.assertEqual(saved[0]["eeprom"]["position_offset"], 123)
        self.assertEqual(saved[1]["eeprom"]["minimum_angle_limit"], 0)
        _, port = self.start()
        self.assertEqual(self.ask(port, 1, READ, bytes([HOMING_OFFSET, 2]), 2)[1], word(123))
        self.assertEqual(self.ask(port, 2, READ, bytes([MIN_LIMIT, 2]), 2)[1], word(0))


if __name__ == "__main__":
    unittest.main()
