"""LeRobot's motor buses as the end-to-end tests replay them: FeetechMotorsBus (STS3215, FT-SCS)
and DynamixelMotorsBus (X series, Protocol 2.0), rebuilt on the repository's own client
(python/dxlemu's `Client`); neither LeRobot nor a servo SDK is used.

What each method sends, and in which order, follows huggingface/lerobot's
`src/lerobot/motors/motors_bus.py` (`reset_calibration`, `set_half_turn_homings`,
`record_ranges_of_motion`, `_normalize`, `_unnormalize`), `motors/feetech/feetech.py` and
`motors/dynamixel/dynamixel.py` (`configure_motors`, `read_calibration`, `write_calibration`,
`_get_half_turn_homings`, `disable_torque`, `enable_torque`), read, not copied. Used by
lerobot_flows_test.py (FEETECH flows) and hands_test.py (calibrations and teleoperation driven by
virtual hands).

A bus writes as LeRobot does: single writes with a status each (an error byte raises BusError,
as LeRobot raises on one), Sync Read in the order of the IDs asked for, Sync Write unanswered.
Under manual timing a Sync Write must be in the daemon's hands before the test steps the clock,
or the goal would be stamped after the step: each one waits until the daemon has read it
(`dxl_client.heard`), and with `check_silence` also checks that nobody answered it (which costs
a 50 ms wait for a byte that must not come: fine for a flow, too slow for a control loop).
"""
from __future__ import annotations

import contextlib
import enum
from typing import Iterable, Iterator, NamedTuple

from dxl_client import Control, Port, assert_unanswered, heard
from dxlemu import feetech
from dxlemu.protocol import BROADCAST_ID, SYNC_WRITE, Client

# STS3215 items under LeRobot's names (models/feetech/sts3215.json).
FIRMWARE_MAJOR, FIRMWARE_MINOR, MODEL_NUMBER, RETURN_DELAY_TIME = 0, 1, 3, 7
MIN_POSITION_LIMIT, MAX_POSITION_LIMIT, MAX_TORQUE_LIMIT = 9, 11, 16
P_COEFFICIENT, D_COEFFICIENT, I_COEFFICIENT, PROTECTION_CURRENT = 21, 22, 23, 28
PHASE, HOMING_OFFSET, OPERATING_MODE, OVERLOAD_TORQUE = 18, 31, 33, 36
TORQUE_ENABLE, ACCELERATION, GOAL_POSITION, LOCK, PRESENT_POSITION = 40, 41, 42, 55, 56
MAXIMUM_ACCELERATION = 85  # read-only in FEETECH's table; LeRobot writes it all the same
STS3215 = 777

RESOLUTION = 4096
MAX_RES = RESOLUTION - 1  # LeRobot's full range: Min_Position_Limit 0 ~ Max_Position_Limit 4095
HALF_TURN = MAX_RES // 2  # LeRobot's middle: the half-turn homing makes Present read 2047
HOMING_SIGN_BIT = 11  # Homing_Offset: sign-magnitude, bit 11 the sign
POSITION_SIGN_BIT = 15  # Present_Position and Goal_Position: bit 15 the sign
FULL_ANGLE = 0x10  # Phase bit 4: full-angle feedback (clear: single-turn)
POSITION_MODE = 0


class Xl330:
    """X-series items under LeRobot's names (models/xl330-m077.json; dynamixel/tables.py's
    X_SERIES_CONTROL_TABLE), each (address, size); the signed ones are LeRobot's
    X_SERIES_ENCODINGS_TABLE (two's complement)."""

    MODEL_NUMBER_M077 = 1190
    RETURN_DELAY_TIME = (9, 1)
    DRIVE_MODE = (10, 1)
    OPERATING_MODE = (11, 1)
    HOMING_OFFSET = (20, 4)
    MAX_POSITION_LIMIT = (48, 4)
    MIN_POSITION_LIMIT = (52, 4)
    TORQUE_ENABLE = (64, 1)
    HARDWARE_ERROR_STATUS = (70, 1)
    GOAL_CURRENT = (102, 2)
    GOAL_POSITION = (116, 4)
    PRESENT_CURRENT = (126, 2)
    PRESENT_POSITION = (132, 4)
    SIGNED = {HOMING_OFFSET, GOAL_CURRENT, GOAL_POSITION, PRESENT_CURRENT, PRESENT_POSITION}
    # dynamixel.py's OperatingMode and DriveMode.
    EXTENDED_POSITION = 4
    CURRENT_POSITION = 5
    INVERTED = 1


class BusError(Exception):
    """What LeRobot raises when a servo answers with an error byte or with the wrong data."""


class Ranges(NamedTuple):
    """What record_ranges_of_motion saw: its mins and maxes, and every reading on the way."""

    mins: dict[int, int]
    maxes: dict[int, int]
    readings: list[dict[int, int]]


class Calibration(NamedTuple):
    """One motor's calibration as LeRobot stores and writes it (MotorCalibration)."""

    homing_offset: int
    range_min: int
    range_max: int
    drive_mode: int = 0


class NormMode(enum.Enum):
    """LeRobot's MotorNormMode."""

    RANGE_M100_100 = "range_m100_100"
    RANGE_0_100 = "range_0_100"
    DEGREES = "degrees"


def normalize(value: int, calibration: Calibration, mode: NormMode,
              apply_drive_mode: bool) -> float:
    """LeRobot's `_normalize` of one raw reading: clamped to the calibrated range and mapped onto
    -100 ~ 100 or 0 ~ 100 (flipped for an inverted drive mode when the bus applies it, which
    FEETECH's does and DYNAMIXEL's leaves to the servo), or degrees from the range's middle."""
    low, high = calibration.range_min, calibration.range_max
    if low == high:
        raise ValueError(f"Invalid calibration: min and max are equal ({calibration})")
    inverted = apply_drive_mode and calibration.drive_mode
    bounded = min(high, max(low, value))
    if mode is NormMode.RANGE_M100_100:
        norm = (bounded - low) / (high - low) * 200 - 100
        return -norm if inverted else norm
    if mode is NormMode.RANGE_0_100:
        norm = (bounded - low) / (high - low) * 100
        return 100 - norm if inverted else norm
    return (value - (low + high) / 2) * 360 / MAX_RES


def unnormalize(value: float, calibration: Calibration, mode: NormMode,
                apply_drive_mode: bool) -> int:
    """LeRobot's `_unnormalize`: the raw goal for a normalized value, truncated by int() as
    LeRobot does."""
    low, high = calibration.range_min, calibration.range_max
    if low == high:
        raise ValueError(f"Invalid calibration: min and max are equal ({calibration})")
    inverted = apply_drive_mode and calibration.drive_mode
    if mode is NormMode.RANGE_M100_100:
        value = -value if inverted else value
        bounded = min(100.0, max(-100.0, value))
        return int((bounded + 100) / 200 * (high - low) + low)
    if mode is NormMode.RANGE_0_100:
        value = 100 - value if inverted else value
        bounded = min(100.0, max(0.0, value))
        return int(bounded / 100 * (high - low) + low)
    return int(value * MAX_RES / 360 + (low + high) / 2)


def encode_homing(value: int) -> bytes:
    """Homing_Offset as LeRobot encodes it: sign-magnitude with the sign in bit 11, refusing a
    magnitude the 11 bits cannot hold with LeRobot's message ("Magnitude ... exceeds 2047")."""
    limit = (1 << HOMING_SIGN_BIT) - 1
    if abs(value) > limit:
        raise ValueError(f"Magnitude {abs(value)} exceeds {limit} (Homing_Offset, sign bit "
                         f"{HOMING_SIGN_BIT})")
    return feetech.encode(value, 2, sign_bit=HOMING_SIGN_BIT)


class CountingPort(Port):
    """A Port that counts the bytes written to it. On a PTY that only this port writes to, that
    is what the daemon's `bytes_in` counts once it has read them all, so a bus on it knows the
    count to wait for without asking the daemon first (one control request less per Sync
    Write, which a control loop feels)."""

    def __init__(self, path: str, baud: int):
        super().__init__(path, baud)
        self.written = 0

    def write(self, data: bytes) -> None:
        super().write(data)
        self.written += len(data)


class MotorsBus:
    """What LeRobot's SerialMotorsBus does the same on both makers: the half-turn homing and the
    recording of the ranges of motion; each maker's subclass reads and writes its items."""

    APPLY_DRIVE_MODE = False

    def __init__(self, client: Client, control: Control, port_name: str, ids: list[int], *,
                 check_silence: bool = True):
        self.client = client
        self.control = control
        self.port_name = port_name
        self.ids = ids
        self.check_silence = check_silence
        self._bytes_in_offset: int | None = None  # bytes_in − written, on a CountingPort

    def sync_read_present(self, motors: list[int] | None = None) -> dict[int, int]:
        raise NotImplementedError

    def reset_calibration(self, motors: list[int] | None = None) -> None:
        raise NotImplementedError

    def write_homing(self, ident: int, offset: int) -> None:
        raise NotImplementedError

    @staticmethod
    def half_turn_homings(present: dict[int, int]) -> dict[int, int]:
        raise NotImplementedError

    def send_unanswered(self, packet: bytes) -> None:
        """Writes a packet nobody answers (Sync Write) and returns once the daemon has read it;
        with `check_silence`, also checks that no reply came (dxl_client.assert_unanswered)."""
        if self.check_silence:
            assert_unanswered(self.control, self.client.port, packet, self.port_name)
            return
        port = self.client.port
        if not isinstance(port, CountingPort):
            before = self.control.call("stats", port=self.port_name)[self.port_name]["bytes_in"]
            port.write(packet)
            heard(self.control, before + len(packet), self.port_name)
            return
        if self._bytes_in_offset is None:
            # Everything written so far was read: each of it was answered before this.
            stats = self.control.call("stats", port=self.port_name)[self.port_name]
            self._bytes_in_offset = stats["bytes_in"] - port.written
        port.write(packet)
        heard(self.control, self._bytes_in_offset + port.written, self.port_name)

    def set_half_turn_homings(self, motors: list[int] | None = None) -> dict[int, int]:
        """reset_calibration, one Sync Read of Present_Position, then each motor's half-turn
        homing offset written in turn (raising at the first one out of reach)."""
        motors = motors or self.ids
        self.reset_calibration(motors)
        homings = self.half_turn_homings(self.sync_read_present(motors))
        for ident, offset in homings.items():
            self.write_homing(ident, offset)
        return homings

    def record_ranges_of_motion(self, person: Iterable[object],
                                motors: list[int] | None = None) -> Ranges:
        """Reads Present_Position of `motors` (all by default) again each time `person` has
        moved the joints a little (LeRobot reads in a loop until ENTER: here until the person is
        done), keeping each motor's smallest and largest reading. A motor never moved is
        refused, as LeRobot does."""
        start = self.sync_read_present(motors)
        mins, maxes, readings = dict(start), dict(start), [start]
        for _ in person:
            present = self.sync_read_present(motors)
            readings.append(present)
            for ident, position in present.items():
                mins[ident] = min(mins[ident], position)
                maxes[ident] = max(maxes[ident], position)
        same = [ident for ident in start if mins[ident] == maxes[ident]]
        if same:
            raise ValueError(f"Some motors have the same min and max values: {same}")
        return Ranges(mins, maxes, readings)


class FeetechBus(MotorsBus):
    """LeRobot's FeetechMotorsBus (protocol 0) call sequences on our FT-SCS client."""

    APPLY_DRIVE_MODE = True

    # Single items.

    def write(self, ident: int, address: int, data: bytes) -> None:
        reply = self.client.write(ident, address, data)
        if reply.error:
            raise BusError(f"write of {address} to {ident}: error byte {reply.error:#04x}")

    def write_byte(self, ident: int, address: int, value: int) -> None:
        self.write(ident, address, bytes([value]))

    def write_word(self, ident: int, address: int, value: int) -> None:
        """A 2-byte item; negative values in sign-magnitude (bit 15), as positions are."""
        self.write(ident, address, feetech.encode(value, 2, sign_bit=POSITION_SIGN_BIT))

    def read(self, ident: int, address: int, size: int, sign_bit: int | None = None) -> int:
        reply = self.client.read(ident, address, size)
        if reply.error or len(reply.data) != size:
            raise BusError(f"read of {address} from {ident}: error byte {reply.error:#04x}, "
                           f"data {reply.data.hex(' ')}")
        return feetech.decode(reply.data, sign_bit=sign_bit)

    # Group instructions.

    def sync_read_raw(self, motors: list[int] | None = None) -> dict[int, bytes]:
        """SYNC READ of Present_Position (56, 2 bytes) of `motors` (all by default): each
        servo's bytes as they came."""
        replies = self.client.sync_read(PRESENT_POSITION, 2, motors or self.ids)
        for ident, reply in replies.items():
            if len(reply.data) != 2:
                raise BusError(f"Present_Position of {ident}: {reply.data.hex(' ')}")
        return {ident: reply.data for ident, reply in replies.items()}

    def sync_read_present(self, motors: list[int] | None = None) -> dict[int, int]:
        """Present_Position of `motors` (all by default), decoded (sign-magnitude, bit 15)."""
        return {ident: feetech.decode(data, sign_bit=POSITION_SIGN_BIT)
                for ident, data in self.sync_read_raw(motors).items()}

    def sync_write_goal(self, goals: dict[int, int]) -> None:
        """SYNC WRITE of Goal_Position (42, 2 bytes), unanswered."""
        params = bytes([GOAL_POSITION, 2]) + b"".join(
            bytes([ident]) + feetech.encode(goal, 2, sign_bit=POSITION_SIGN_BIT)
            for ident, goal in goals.items())
        self.send_unanswered(self.client.packet(BROADCAST_ID, feetech.SYNC_WRITE, params))

    # LeRobot's steps.

    def connect(self) -> tuple[int, int]:
        """The connect handshake: ping every ID and read its model number (FEETECH's SDK's
        ping), then the firmware bytes 0 and 1 of every motor, which must all be equal.
        Returns the firmware (major, minor)."""
        for ident in self.ids:
            reply = self.client.ping(ident)
            if reply.error:
                raise BusError(f"ping of {ident}: error byte {reply.error:#04x}")
            model = self.read(ident, MODEL_NUMBER, 2)
            if model != STS3215:
                raise BusError(f"motor {ident} is model {model}, not the sts3215 (777) expected")
        firmware = {ident: (self.read(ident, FIRMWARE_MAJOR, 1),
                            self.read(ident, FIRMWARE_MINOR, 1)) for ident in self.ids}
        if len(set(firmware.values())) != 1:
            raise BusError(f"motors of different firmware: {firmware}")
        return firmware[self.ids[0]]

    def configure_motors(self) -> None:
        """Return_Delay_Time 0, Maximum_Acceleration 254, Acceleration 254, and Phase's bit 4
        cleared where it is set (single-turn feedback)."""
        for ident in self.ids:
            self.write_byte(ident, RETURN_DELAY_TIME, 0)
            self.write_byte(ident, MAXIMUM_ACCELERATION, 254)
            self.write_byte(ident, ACCELERATION, 254)
            phase = self.read(ident, PHASE, 1)
            if phase & FULL_ANGLE:
                self.write_byte(ident, PHASE, phase & ~FULL_ANGLE)

    def disable_torque(self) -> None:
        """Torque_Enable 0, then Lock 0 (EEPROM writes from now on survive power-off)."""
        for ident in self.ids:
            self.write_byte(ident, TORQUE_ENABLE, 0)
            self.write_byte(ident, LOCK, 0)

    def enable_torque(self) -> None:
        """Torque_Enable 1, then Lock 1."""
        for ident in self.ids:
            self.write_byte(ident, TORQUE_ENABLE, 1)
            self.write_byte(ident, LOCK, 1)

    @contextlib.contextmanager
    def torque_disabled(self) -> Iterator[None]:
        self.disable_torque()
        try:
            yield
        finally:
            self.enable_torque()

    def set_position_mode(self) -> None:
        for ident in self.ids:
            self.write_byte(ident, OPERATING_MODE, POSITION_MODE)

    def reset_calibration(self, motors: list[int] | None = None) -> None:
        """Homing_Offset 0 and the full range 0 ~ 4095 on each motor."""
        for ident in motors or self.ids:
            self.write(ident, HOMING_OFFSET, encode_homing(0))
            self.write_word(ident, MIN_POSITION_LIMIT, 0)
            self.write_word(ident, MAX_POSITION_LIMIT, MAX_RES)

    def write_homing(self, ident: int, offset: int) -> None:
        self.write(ident, HOMING_OFFSET, encode_homing(offset))

    @staticmethod
    def half_turn_homings(present: dict[int, int]) -> dict[int, int]:
        """The offset that makes each Present_Position read the middle, 2047: Present =
        Actual − Homing_Offset on FEETECH."""
        return {ident: position - HALF_TURN for ident, position in present.items()}

    def write_calibration(self, calibration: dict[int, Calibration]) -> None:
        for ident, motor in calibration.items():
            self.write(ident, HOMING_OFFSET, encode_homing(motor.homing_offset))
            self.write_word(ident, MIN_POSITION_LIMIT, motor.range_min)
            self.write_word(ident, MAX_POSITION_LIMIT, motor.range_max)

    def read_calibration(self) -> dict[int, Calibration]:
        return {ident: Calibration(self.read(ident, HOMING_OFFSET, 2, HOMING_SIGN_BIT),
                                   self.read(ident, MIN_POSITION_LIMIT, 2),
                                   self.read(ident, MAX_POSITION_LIMIT, 2))
                for ident in self.ids}

    def configure_follower(self, gains: tuple[int, int, int] = (16, 0, 32),
                           gripper: int | None = None) -> None:
        """so_follower.py's configure(): inside torque_disabled, configure_motors, then per
        motor Operating_Mode 0 and the P, I and D coefficients; on the gripper Max_Torque_Limit
        500, Protection_Current 250 and Overload_Torque 25. Ends with the torque on."""
        p, i, d = gains
        with self.torque_disabled():
            self.configure_motors()
            for ident in self.ids:
                self.write_byte(ident, OPERATING_MODE, POSITION_MODE)
                self.write_byte(ident, P_COEFFICIENT, p)
                self.write_byte(ident, I_COEFFICIENT, i)
                self.write_byte(ident, D_COEFFICIENT, d)
                if ident == gripper:
                    self.write_word(ident, MAX_TORQUE_LIMIT, 500)
                    self.write_word(ident, PROTECTION_CURRENT, 250)
                    self.write_byte(ident, OVERLOAD_TORQUE, 25)

    def phases(self) -> dict[int, int]:
        return {ident: self.read(ident, PHASE, 1) for ident in self.ids}

    def torques(self) -> dict[int, int]:
        return {ident: self.read(ident, TORQUE_ENABLE, 1) for ident in self.ids}


class DynamixelBus(MotorsBus):
    """LeRobot's DynamixelMotorsBus (Protocol 2.0) call sequences on our client: items as
    Xl330's (address, size) pairs, the signed ones in two's complement."""

    APPLY_DRIVE_MODE = False

    @staticmethod
    def _bytes(item: tuple[int, int], value: int) -> bytes:
        _, size = item
        return value.to_bytes(size, "little", signed=item in Xl330.SIGNED)

    @staticmethod
    def _value(item: tuple[int, int], data: bytes) -> int:
        return int.from_bytes(data, "little", signed=item in Xl330.SIGNED)

    def write(self, ident: int, item: tuple[int, int], value: int) -> None:
        reply = self.client.write(ident, item[0], self._bytes(item, value))
        if reply.error:
            raise BusError(f"write of {item} to {ident}: error byte {reply.error:#04x}")

    def read(self, ident: int, item: tuple[int, int]) -> int:
        address, size = item
        reply = self.client.read(ident, address, size)
        if reply.error or len(reply.data) != size:
            raise BusError(f"read of {item} from {ident}: error byte {reply.error:#04x}, "
                           f"data {reply.data.hex(' ')}")
        return self._value(item, reply.data)

    def sync_read(self, item: tuple[int, int], motors: list[int] | None = None) -> dict[int, int]:
        """Sync Read of `item`. The error byte is not looked at: LeRobot's _sync_read checks
        only that the exchange succeeded, so a servo with a hardware error (the alert bit)
        still reads."""
        address, size = item
        replies = self.client.sync_read(address, size, motors or self.ids)
        for ident, reply in replies.items():
            if len(reply.data) != size:
                raise BusError(f"{item} of {ident}: data {reply.data.hex(' ')}")
        return {ident: self._value(item, reply.data) for ident, reply in replies.items()}

    def sync_read_present(self, motors: list[int] | None = None) -> dict[int, int]:
        return self.sync_read(Xl330.PRESENT_POSITION, motors)

    def sync_write(self, item: tuple[int, int], values: dict[int, int]) -> None:
        address, size = item
        params = address.to_bytes(2, "little") + size.to_bytes(2, "little") + b"".join(
            bytes([ident]) + self._bytes(item, value) for ident, value in values.items())
        self.send_unanswered(self.client.packet(BROADCAST_ID, SYNC_WRITE, params))

    def sync_write_goal(self, goals: dict[int, int]) -> None:
        self.sync_write(Xl330.GOAL_POSITION, goals)

    # LeRobot's steps.

    def connect(self) -> None:
        """The handshake, _assert_motors_exist: a Ping of every ID, its model number compared."""
        for ident in self.ids:
            reply = self.client.ping(ident)
            if reply.error:
                raise BusError(f"ping of {ident}: error byte {reply.error:#04x}")
            model = int.from_bytes(reply.data[:2], "little")
            if model != Xl330.MODEL_NUMBER_M077:
                raise BusError(f"motor {ident} is model {model}, not the xl330-m077 expected")

    def read_calibration(self) -> dict[int, Calibration]:
        """Four Sync Reads: Homing_Offset, Min_ and Max_Position_Limit, Drive_Mode."""
        offsets = self.sync_read(Xl330.HOMING_OFFSET)
        mins = self.sync_read(Xl330.MIN_POSITION_LIMIT)
        maxes = self.sync_read(Xl330.MAX_POSITION_LIMIT)
        drive_modes = self.sync_read(Xl330.DRIVE_MODE)
        return {ident: Calibration(offsets[ident], mins[ident], maxes[ident], drive_modes[ident])
                for ident in self.ids}

    def write_calibration(self, calibration: dict[int, Calibration]) -> None:
        for ident, motor in calibration.items():
            self.write(ident, Xl330.HOMING_OFFSET, motor.homing_offset)
            self.write(ident, Xl330.MIN_POSITION_LIMIT, motor.range_min)
            self.write(ident, Xl330.MAX_POSITION_LIMIT, motor.range_max)

    def reset_calibration(self, motors: list[int] | None = None) -> None:
        for ident in motors or self.ids:
            self.write(ident, Xl330.HOMING_OFFSET, 0)
            self.write(ident, Xl330.MIN_POSITION_LIMIT, 0)
            self.write(ident, Xl330.MAX_POSITION_LIMIT, MAX_RES)

    def write_homing(self, ident: int, offset: int) -> None:
        self.write(ident, Xl330.HOMING_OFFSET, offset)

    @staticmethod
    def half_turn_homings(present: dict[int, int]) -> dict[int, int]:
        """On DYNAMIXEL Present = Actual + Homing_Offset: the offset is 2047 − the reading."""
        return {ident: HALF_TURN - position for ident, position in present.items()}

    def disable_torque(self, motors: list[int] | None = None) -> None:
        for ident in motors or self.ids:
            self.write(ident, Xl330.TORQUE_ENABLE, 0)

    def enable_torque(self, motors: list[int] | None = None) -> None:
        for ident in motors or self.ids:
            self.write(ident, Xl330.TORQUE_ENABLE, 1)

    def configure_motors(self) -> None:
        """Return_Delay_Time 0 on every motor."""
        for ident in self.ids:
            self.write(ident, Xl330.RETURN_DELAY_TIME, 0)
