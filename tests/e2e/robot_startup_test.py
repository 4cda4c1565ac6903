"""End-to-end: each robot profile (robots/*.json, docs/robots.md) served by `dxlemu run --robot
NAME` over a real PTY, driven through the start-up its own software makes, every answer checked.

Each test replays, in order, the packets the robot's software sends when it starts (read from its
public source, cited in the profile's header and in each test's docstring): which IDs it pings
and the model numbers it expects, the reads its checks make, the settings its configure step
writes, how it maps and reads its state, and a first move where the software makes one. The
readiness line must list the profile's servos. The software itself is not run (it needs ROS 2,
PyTorch or a camera stack); these are its bus conversations, rebuilt here with the repository's
own Python client (python/dxlemu, standard library only).
"""
import array
import fcntl
import os
import tempfile
import termios
import unittest

from dxl_client import Control, Daemon, assert_unanswered, heard, timeout_scale
from dxlemu.protocol import BROADCAST_ID, FEETECH, PING, Client

# Fast Sync Read (Protocol 2.0): one status from 0xFE with a block per servo.
FAST_SYNC_READ = 0x8A
FAST_REPLY_ID = 0xFE

# How far the replays step the clock between two looks at a moving servo.
STEP_MS = 20

# Linux termios2 (asm-generic/termbits.h): a baud rate that has no B constant (6 Mbit/s).
TCGETS2, TCSETS2 = 0x802C542A, 0x402C542B
CBAUD, BOTHER = 0o010017, 0o010000
TERMIOS2_WORDS = 11  # c_iflag, c_oflag, c_cflag, c_lflag, c_line + c_cc[19], c_ispeed, c_ospeed
CFLAG, ISPEED, OSPEED = 2, 9, 10


def set_any_baud(port, bps: int) -> None:
    """Sets `port` (a raw dxlemu.port.Port) to `bps` with BOTHER, as pyserial does for rates
    without a termios constant; the daemon reads it back with TCGETS2 (docs/timing.md)."""
    attr = array.array("I", [0] * TERMIOS2_WORDS)
    fcntl.ioctl(port.fd, TCGETS2, attr, True)
    attr[CFLAG] = (attr[CFLAG] & ~CBAUD) | BOTHER
    attr[ISPEED] = attr[OSPEED] = bps
    fcntl.ioctl(port.fd, TCSETS2, attr)
    port.flush_input()


def le(value: int, size: int) -> bytes:
    return value.to_bytes(size, "little", signed=value < 0)


def value(data: bytes) -> int:
    return int.from_bytes(data, "little", signed=True)


class RobotBus(unittest.TestCase):
    """One profile's daemon and a client on its link."""

    def serve(self, robot: str, baud: int, protocol,
              expected_servos: list[tuple[int, str]]) -> Client:
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        link = os.path.join(tmp.name, "tty")
        # The replays check what the servos answer, not when: manual timing, whose replies go
        # out at once and are never dropped as late, and whose clock moves the servos only when
        # the replay steps it.
        daemon = Daemon("--robot", robot, "--link", link, "--timing", "manual",
                        "--control", os.path.join(tmp.name, "ctl"))
        self.addCleanup(daemon.stop)
        self.control = Control(daemon.ready["control"])
        self.addCleanup(self.control.close)
        self.port_name = daemon.ready["port"]
        self.assertEqual(daemon.ready["link"], link)
        self.assertEqual([(s["id"], s["model"]) for s in daemon.ready["servos"]], expected_servos)
        client = Client(link, baud=min(baud, 1_000_000), protocol=protocol,
                        timeout=0.5 * timeout_scale())
        if baud > 1_000_000 and baud not in (2_000_000, 3_000_000, 4_000_000):
            set_any_baud(client.port, baud)
        elif baud > 1_000_000:
            client.port.set_baud(baud)
        self.addCleanup(client.close)
        return client

    def ok(self, reply, what: str = "") -> bytes:
        self.assertEqual(reply.error, 0, f"error byte {reply.error:#04x} {what}")
        return reply.data

    def write(self, client: Client, ident: int, address: int, v: int, size: int) -> None:
        self.ok(client.write_int(ident, address, v, size), f"writing {v} at {address} of {ident}")

    def read(self, client: Client, ident: int, address: int, size: int) -> int:
        data = self.ok(client.read(ident, address, size), f"reading {address} of {ident}")
        self.assertEqual(len(data), size)
        return value(data) if size > 1 else data[0]

    def sync_read(self, client: Client, address: int, size: int, ids) -> dict[int, int]:
        replies = client.sync_read(address, size, ids)
        return {i: value(self.ok(r, f"Sync Read {address} of {i}")) for i, r in replies.items()}

    def fast_sync_read(self, client: Client, address: int, size: int, ids) -> dict[int, bytes] | None:
        """Fast Sync Read: the data of each servo's block, or None when nobody answered."""
        ids = list(ids)
        packet = client.packet(BROADCAST_ID, FAST_SYNC_READ,
                               le(address, 2) + le(size, 2) + bytes(ids))
        before = self.control.stats(self.port_name)[self.port_name]
        client.port.write(packet)
        after = heard(self.control, before["bytes_in"] + len(packet), self.port_name)
        if after["replies"] == before["replies"]:
            self.assertEqual(client.port.read(1, timeout=0.05), b"")
            return None
        status = client.port.status2(0.5 * timeout_scale())
        self.assertIsNotNone(status, "a reply was counted but none came")
        self.assertEqual(status.id, FAST_REPLY_ID)
        # Blocks: ID, data, CRC (2), then the next block's error; the last CRC is the packet's.
        out, rest, error = {}, status.params, status.error
        for ident in ids:
            self.assertEqual((rest[0], error), (ident, 0), f"fast block of {ident}")
            out[ident] = rest[1:1 + size]
            rest = rest[1 + size + 2:]
            error = rest[0] if rest else 0
            rest = rest[1:]
        return out

    def silent(self, client: Client, ident: int) -> None:
        """Nobody answers a Ping of `ident`."""
        assert_unanswered(self.control, client.port, client.packet(ident, PING), self.port_name)

    def wait_until(self, condition, what: str, seconds: float = 5.0):
        """Steps the clock STEP_MS at a time until `condition()` is True, for `seconds` of
        simulated time at most; it returns True or what to show when it never is."""
        for _ in range(round(seconds * 1000 / STEP_MS)):
            if condition() is True:
                return
            self.control.clock_step(ms=STEP_MS)
        got = condition()
        self.assertIs(got, True, f"{what} after {seconds} s: {got}")


# DYNAMIXEL X series items (models/xm430-w350.json and the other X files).
X_RETURN_DELAY, X_DRIVE_MODE, X_OPERATING_MODE, X_SECONDARY_ID = 9, 10, 11, 12
X_HOMING_OFFSET, X_VELOCITY_LIMIT, X_MAX_POSITION, X_MIN_POSITION = 20, 44, 48, 52
X_TORQUE, X_POSITION_D, X_POSITION_I, X_POSITION_P = 64, 80, 82, 84
X_GOAL_CURRENT, X_PROFILE_ACCELERATION, X_PROFILE_VELOCITY, X_GOAL_POSITION = 102, 108, 112, 116
X_PRESENT_CURRENT, X_PRESENT_VELOCITY, X_PRESENT_POSITION = 126, 128, 132
X_INDIRECT_WRITE_ADDRESS, X_INDIRECT_WRITE_DATA = 168, 224  # Indirect Address/Data 1
X_INDIRECT_READ_ADDRESS, X_INDIRECT_READ_DATA = 578, 634    # Indirect Address/Data 29
POSITION_MODE, EXTENDED_POSITION_MODE, CURRENT_POSITION_MODE, PWM_MODE = 3, 4, 5, 16
POWER_ON_POSITION = 2048  # where the X model files put the shaft at power-on
# Drive Mode's reverse bit turns the sign of Present Position (docs/motion.md): a reversed servo
# at rest reads -2048.
REVERSED_POWER_ON_POSITION = -POWER_ON_POSITION

MODEL = {"xm430-w350": 1020, "xl430-w250": 1060, "xl330-m077": 1190, "xl330-m288": 1200,
         "xl-320": 350, "ym080-230-r099-rh": 4150, "ym070-210-r099-rh": 4030}


class LeRobotDynamixel(RobotBus):
    """LeRobot's DynamixelMotorsBus (src/lerobot/motors/motors_bus.py, motors/dynamixel/
    dynamixel.py) driving the Koch v1.1 arms (robots/koch_follower, teleoperators/koch_leader)."""

    def connect(self, client: Client, models: dict[int, str]) -> None:
        # _assert_motors_exist: a Ping per ID, the model number in its reply.
        for ident, model in models.items():
            data = self.ok(client.ping(ident))
            self.assertEqual(value(data[:2]), MODEL[model], f"model number of {ident}")
        self.silent(client, max(models) + 1)
        # is_calibrated -> read_calibration: four Sync Reads, factory values on a new arm.
        ids = list(models)
        self.assertEqual(self.sync_read(client, X_HOMING_OFFSET, 4, ids), dict.fromkeys(ids, 0))
        self.assertEqual(self.sync_read(client, X_MIN_POSITION, 4, ids), dict.fromkeys(ids, 0))
        self.assertEqual(self.sync_read(client, X_MAX_POSITION, 4, ids), dict.fromkeys(ids, 4095))
        self.assertEqual(self.sync_read(client, X_DRIVE_MODE, 1, ids), dict.fromkeys(ids, 0))

    def configure_modes(self, client: Client, ids: list[int]) -> None:
        # disable_torque, configure_motors (Return_Delay_Time 0), then the operating modes.
        for ident in ids:
            self.write(client, ident, X_TORQUE, 0, 1)
        for ident in ids:
            self.write(client, ident, X_RETURN_DELAY, 0, 1)
        for ident in ids[:-1]:
            self.write(client, ident, X_OPERATING_MODE, EXTENDED_POSITION_MODE, 1)
        self.write(client, ids[-1], X_OPERATING_MODE, CURRENT_POSITION_MODE, 1)

    def test_koch_follower(self):
        models = {1: "xl430-w250", 2: "xl430-w250", 3: "xl330-m288", 4: "xl330-m288",
                  5: "xl330-m288", 6: "xl330-m288"}
        client = self.serve("koch-v1.1-follower", 1_000_000, 2, list(models.items()))
        self.connect(client, models)
        ids = list(models)
        self.configure_modes(client, ids)
        # The elbow's PID gains, still with torque off (torque_disabled()).
        self.write(client, 3, X_POSITION_P, 1500, 2)
        self.write(client, 3, X_POSITION_I, 0, 2)
        self.write(client, 3, X_POSITION_D, 600, 2)
        for ident in ids:  # leaving torque_disabled(): torque on
            self.write(client, ident, X_TORQUE, 1, 1)
        # get_observation: Sync Read Present_Position; send_action: Sync Write Goal_Position.
        self.assertEqual(self.sync_read(client, X_PRESENT_POSITION, 4, ids),
                         dict.fromkeys(ids, POWER_ON_POSITION))
        goals = {i: POWER_ON_POSITION + 100 * i for i in ids}
        client.sync_write(X_GOAL_POSITION, {i: le(g, 4) for i, g in goals.items()})

        def arrived():
            present = self.sync_read(client, X_PRESENT_POSITION, 4, ids)
            return all(abs(present[i] - goals[i]) <= 5 for i in ids) or present
        self.wait_until(arrived, "not at the goals")
        self.assertEqual(self.read(client, 6, X_OPERATING_MODE, 1), CURRENT_POSITION_MODE)
        self.assertEqual(self.read(client, 3, X_POSITION_P, 2), 1500)

    def test_koch_leader(self):
        models = dict.fromkeys(range(1, 7), "xl330-m077")
        client = self.serve("koch-v1.1-leader", 1_000_000, 2, list(models.items()))
        self.connect(client, models)
        ids = list(models)
        self.configure_modes(client, ids)
        self.write(client, 6, X_TORQUE, 1, 1)  # enable_torque("gripper"): the trigger
        # get_action: Sync Read Present_Position; only the gripper holds torque.
        self.assertEqual(self.sync_read(client, X_PRESENT_POSITION, 4, ids),
                         dict.fromkeys(ids, POWER_ON_POSITION))
        self.assertEqual(self.sync_read(client, X_TORQUE, 1, ids), {**dict.fromkeys(ids, 0), 6: 1})
        self.assertEqual(self.read(client, 1, X_OPERATING_MODE, 1), EXTENDED_POSITION_MODE)


# FEETECH STS items (models/feetech/sts3215.json; LeRobot's motors/feetech/tables.py).
FT_FIRMWARE_MAJOR, FT_FIRMWARE_MINOR, FT_MODEL, FT_RETURN_DELAY = 0, 1, 3, 7
FT_MIN_POSITION, FT_MAX_POSITION, FT_MAX_TORQUE, FT_PHASE = 9, 11, 16, 18
FT_P, FT_D, FT_I, FT_PROTECTION_CURRENT, FT_HOMING, FT_OPERATING_MODE = 21, 22, 23, 28, 31, 33
FT_OVERLOAD_TORQUE, FT_TORQUE, FT_ACCELERATION, FT_LOCK, FT_PRESENT = 36, 40, 41, 55, 56
FT_MAXIMUM_ACCELERATION = 85  # a read-only factory parameter in FEETECH's table
STS3215 = 777
PHASE_ANGLE_FEEDBACK = 0x10


class LeRobotFeetech(RobotBus):
    """LeRobot's FeetechMotorsBus (src/lerobot/motors/feetech/feetech.py) driving the SO-101
    arms (robots/so_follower, teleoperators/so_leader)."""

    IDS = [1, 2, 3, 4, 5, 6]

    def connect_and_configure(self, robot: str) -> Client:
        client = self.serve(robot, 1_000_000, FEETECH, [(i, "sts3215") for i in self.IDS])
        # _assert_motors_exist: scservo_sdk's ping is a Ping, then a Read of the model number.
        for ident in self.IDS:
            self.ok(client.ping(ident))
            self.assertEqual(self.read(client, ident, FT_MODEL, 2), STS3215)
        self.silent(client, 7)
        # _assert_same_firmware: major and minor version of each, all equal.
        versions = {(self.read(client, i, FT_FIRMWARE_MAJOR, 1),
                     self.read(client, i, FT_FIRMWARE_MINOR, 1)) for i in self.IDS}
        self.assertEqual(len(versions), 1, versions)
        # read_calibration: limits and offset of each, factory values on a new arm.
        for ident in self.IDS:
            self.assertEqual(self.read(client, ident, FT_MIN_POSITION, 2), 0)
            self.assertEqual(self.read(client, ident, FT_MAX_POSITION, 2), 4095)
            self.assertEqual(self.read(client, ident, FT_HOMING, 2), 0)
        # configure(): disable_torque (Torque_Enable 0, Lock 0), configure_motors, modes.
        for ident in self.IDS:
            self.write(client, ident, FT_TORQUE, 0, 1)
            self.write(client, ident, FT_LOCK, 0, 1)
        for ident in self.IDS:
            self.write(client, ident, FT_RETURN_DELAY, 0, 1)
            # Refused silently: no error bit, nothing changes (docs/feetech.md).
            self.write(client, ident, FT_MAXIMUM_ACCELERATION, 254, 1)
            self.write(client, ident, FT_ACCELERATION, 254, 1)
            phase = self.read(client, ident, FT_PHASE, 1)
            if phase & PHASE_ANGLE_FEEDBACK:
                self.write(client, ident, FT_PHASE, phase & ~PHASE_ANGLE_FEEDBACK, 1)
        self.assertEqual(self.read(client, 1, FT_MAXIMUM_ACCELERATION, 1), 0)
        self.assertEqual(self.read(client, 1, FT_ACCELERATION, 1), 254)
        return client

    def test_so101_follower(self):
        client = self.connect_and_configure("so101-follower")
        for ident in self.IDS:
            self.write(client, ident, FT_OPERATING_MODE, 0, 1)
            self.write(client, ident, FT_P, 16, 1)  # config_so_follower.py's defaults
            self.write(client, ident, FT_I, 0, 1)
            self.write(client, ident, FT_D, 32, 1)
        self.write(client, 6, FT_MAX_TORQUE, 500, 2)  # the gripper: half torque, half current
        self.write(client, 6, FT_PROTECTION_CURRENT, 250, 2)
        self.write(client, 6, FT_OVERLOAD_TORQUE, 25, 1)
        for ident in self.IDS:  # leaving torque_disabled(): enable_torque
            self.write(client, ident, FT_TORQUE, 1, 1)
            self.write(client, ident, FT_LOCK, 1, 1)
        self.assertEqual(self.sync_read(client, FT_PRESENT, 2, self.IDS),
                         dict.fromkeys(self.IDS, POWER_ON_POSITION))
        self.assertEqual(self.read(client, 6, FT_MAX_TORQUE, 2), 500)
        self.assertEqual(self.read(client, 2, FT_P, 1), 16)

    def test_so101_leader(self):
        client = self.connect_and_configure("so101-leader")
        for ident in self.IDS:
            self.write(client, ident, FT_OPERATING_MODE, 0, 1)
        # get_action: Sync Read Present_Position; torque stays off (moved by hand).
        self.assertEqual(self.sync_read(client, FT_PRESENT, 2, self.IDS),
                         dict.fromkeys(self.IDS, POWER_ON_POSITION))
        self.assertEqual({i: self.read(client, i, FT_TORQUE, 1) for i in self.IDS},
                         dict.fromkeys(self.IDS, 0))


class DynamixelHardwareInterface(RobotBus):
    """ROBOTIS dynamixel_hardware_interface (src/dynamixel_hardware_interface.cpp on_init and
    InitItem, src/dynamixel/dynamixel.cpp InitDxlComm, InitTorqueStates, AddIndirectRead/Write)
    with the parameters of open_manipulator's ros2_control xacros."""

    def init_item(self, client: Client, ident: int, model: str, torque: int,
                  operating_mode: int, limits: list, others: list) -> None:
        # InitDxlComm: Ping, the model number in the reply picks the model file.
        self.assertEqual(value(self.ok(client.ping(ident))[:2]), MODEL[model])
        # InitTorqueStates: read Torque Enable (a write of 0 only when it is on).
        self.assertEqual(self.read(client, ident, torque, 1), 0)
        # InitItem: Operating Mode first, then the "Limit" items, then the others.
        self.write(client, ident, *operating_mode)
        for address, v, size in limits + others:
            self.write(client, ident, address, v, size)

    def map_indirect(self, client: Client, ident: int, base: int, items: list) -> None:
        """AddIndirectRead/Write: one 2-byte Indirect Address per byte of each item."""
        slot = 0
        for address, size in items:
            for i in range(size):
                self.write(client, ident, base + 2 * slot, address + i, 2)
                slot += 1

    def test_openmanipulator_x(self):
        ids = [11, 12, 13, 14, 15]
        client = self.serve("openmanipulator-x", 1_000_000, 2, [(i, "xm430-w350") for i in ids])
        self.silent(client, 1)  # not the factory ID: the arm ships renumbered
        joint = [(X_DRIVE_MODE, 4, 1), (X_POSITION_P, 800, 2), (X_POSITION_I, 100, 2),
                 (X_POSITION_D, 100, 2), (X_PROFILE_VELOCITY, 20, 4),
                 (X_PROFILE_ACCELERATION, 10, 4), (X_RETURN_DELAY, 0, 1)]
        gripper = [(X_DRIVE_MODE, 5, 1), (X_PROFILE_VELOCITY, 20, 4),
                   (X_PROFILE_ACCELERATION, 10, 4), (X_RETURN_DELAY, 0, 1),
                   (X_GOAL_CURRENT, 200, 2)]
        for ident in ids:
            mode = POSITION_MODE if ident != 15 else CURRENT_POSITION_MODE
            self.init_item(client, ident, "xm430-w350", X_TORQUE, (X_OPERATING_MODE, mode, 1),
                           [], joint if ident != 15 else gripper)
        # InitDxlReadItems: torque off, the state items mapped to Indirect Data Read (29),
        # then read with Fast Sync Read: position 4, velocity 4, current 2 bytes.
        state = [(X_PRESENT_POSITION, 4), (X_PRESENT_VELOCITY, 4), (X_PRESENT_CURRENT, 2)]
        for ident in ids:
            self.write(client, ident, X_TORQUE, 0, 1)
            self.map_indirect(client, ident, X_INDIRECT_READ_ADDRESS, state)
        blocks = self.fast_sync_read(client, X_INDIRECT_READ_DATA, 10, ids)
        self.assertIsNotNone(blocks, "no Fast Sync Read reply")
        for ident, data in blocks.items():
            at_rest = POWER_ON_POSITION if ident != 15 else REVERSED_POWER_ON_POSITION
            self.assertEqual((value(data[:4]), value(data[4:8]), value(data[8:])),
                             (at_rest, 0, 0), f"state of {ident}")
        # InitDxlWriteItems: Goal Position through Indirect Data Write (1); start(): torque on.
        for ident in ids:
            self.write(client, ident, X_TORQUE, 0, 1)
            self.map_indirect(client, ident, X_INDIRECT_WRITE_ADDRESS, [(X_GOAL_POSITION, 4)])
        for ident in ids:
            self.write(client, ident, X_TORQUE, 1, 1)
        goals = {i: POWER_ON_POSITION - 50 * (i - 10) for i in ids}
        client.sync_write(X_INDIRECT_WRITE_DATA, {i: le(g, 4) for i, g in goals.items()})
        self.assertEqual(self.read(client, 12, X_GOAL_POSITION, 4), goals[12])

        def arrived():
            got = {i: value(d[:4]) for i, d in
                   self.fast_sync_read(client, X_INDIRECT_READ_DATA, 10, ids).items()}
            return all(abs(got[i] - goals[i]) <= 5 for i in ids) or got
        self.wait_until(arrived, "not at the goals")

    def test_openmanipulator_y(self):
        """omy_3m_position.ros2_control.xacro at 6 Mbit/s (the xacro says 6,250,000: see the
        profile's notes). The OMY hat (ID 200) and end unit (210) are not in the catalogue."""
        ids = [1, 2, 3, 4, 5, 6]
        models = {i: "ym080-230-r099-rh" if i <= 2 else "ym070-210-r099-rh" for i in ids}
        client = self.serve("openmanipulator-y", 6_000_000, 2, list(models.items()))
        self.silent(client, 200)
        # DYNAMIXEL-Y items (models/ym080-230-r099-rh.json).
        y_return_delay, y_drive_mode, y_operating_mode, y_homing = 13, 32, 33, 52
        y_acceleration_limit, y_velocity_limit, y_velocity_i, y_velocity_p = 68, 72, 212, 216
        y_position_p, y_profile_acceleration, y_profile_velocity = 232, 240, 244
        y_profile_acceleration_time, y_profile_time, y_torque = 248, 252, 512
        y_present_current, y_present_velocity, y_present_position = 546, 548, 552
        y_indirect_read_address, y_indirect_read_data = 384, 698  # Indirect Address/Data 65
        for ident in ids:
            velocity = 3591 if ident <= 2 else 6486
            gains = {1: (41387, 1565630), 2: (41387, 1565630)}.get(ident, (18184, 1585331))
            others = [(y_drive_mode, 4 if ident % 2 else 5, 1), (y_profile_velocity, velocity, 4),
                      (y_profile_acceleration, 8050, 4), (y_return_delay, 0, 1),
                      (y_position_p, 1583185, 4), (y_velocity_p, gains[0], 4),
                      (y_velocity_i, gains[1], 4), (y_profile_acceleration_time, 20, 4),
                      (y_profile_time, 40, 4)]
            if ident == 1:
                others.append((y_homing, 0, 4))
            self.init_item(client, ident, models[ident], y_torque,
                           (y_operating_mode, POSITION_MODE, 1),
                           [(y_velocity_limit, velocity, 4), (y_acceleration_limit, 8050, 4)],
                           others)
        state = [(y_present_position, 4), (y_present_velocity, 4), (y_present_current, 2)]
        for ident in ids:
            self.write(client, ident, y_torque, 0, 1)
            self.map_indirect(client, ident, y_indirect_read_address, state)
        # The interface tries Fast Sync Read first and falls back to Sync Read; dxlemu's
        # DYNAMIXEL-Y models do not answer Fast reads (docs/protocol-coverage.md).
        self.assertIsNone(self.fast_sync_read(client, y_indirect_read_data, 10, ids))
        replies = client.sync_read(y_indirect_read_data, 10, ids)
        for ident, reply in replies.items():
            data = self.ok(reply)
            self.assertEqual((value(data[4:8]), value(data[8:])), (0, 0), f"state of {ident}")
            self.assertEqual(value(data[:4]), self.read(client, ident, y_present_position, 4))
        self.assertEqual(self.read(client, 2, y_drive_mode, 1), 5)
        self.assertEqual(self.read(client, 3, y_velocity_limit, 4), 6486)


class Interbotix(RobotBus):
    """interbotix_xs_sdk (Interbotix/interbotix_ros_core, interbotix_xs_sdk/src/xs_sdk_obj.cpp)
    with interbotix_xsarm_control's wx250.yaml and modes.yaml: robot_ping_motors (a Ping per
    motor, torque off), robot_load_motor_configs (the yaml's registers, load_configs is true by
    default), robot_init_operating_modes (per joint, shadows included: Drive_Mode read and bit 2
    set for a time-based profile, Operating Mode, Profile_Velocity/Acceleration, torque on), then
    joint states by Sync Read from Present_Current (126), 12 bytes. The xs_sdk walks its motors
    in an unordered_map's order; the replay takes them by ID."""

    MODELS = {i: "xm430-w350" if i <= 6 else "xl430-w250" for i in range(1, 9)}
    LIMITS = {1: (0, 4095), 2: (819, 3345), 3: (819, 3345), 4: (648, 3094), 5: (648, 3094),
              6: (910, 3447), 7: (0, 4095), 8: (0, 4095)}
    DRIVE = {3: 1, 5: 1, 6: 1}
    SECONDARY = {3: 2, 5: 4}
    JOINTS = [1, 2, 4, 6, 7]  # the arm group's joints; 3 and 5 are shadows of 2 and 4
    BAUD_1M = 3  # Baud_Rate 3: 1,000,000 bit/s

    def start(self) -> Client:
        client = self.serve("widowx-250", 1_000_000, 2, list(self.MODELS.items()))
        for ident, model in self.MODELS.items():  # robot_ping_motors
            self.assertEqual(value(self.ok(client.ping(ident))[:2]), MODEL[model])
            self.write(client, ident, X_TORQUE, 0, 1)
        for ident in self.MODELS:  # robot_load_motor_configs: wx250.yaml's motors, in order
            lo, hi = self.LIMITS[ident]
            for address, v, size in [(8, self.BAUD_1M, 1), (X_RETURN_DELAY, 0, 1),
                                     (X_DRIVE_MODE, self.DRIVE.get(ident, 0), 1),
                                     (X_VELOCITY_LIMIT, 131, 4), (X_MIN_POSITION, lo, 4),
                                     (X_MAX_POSITION, hi, 4),
                                     (X_SECONDARY_ID, self.SECONDARY.get(ident, 255), 1)]:
                self.write(client, ident, address, v, size)
        # robot_init_operating_modes: the arm group (position, time-based profile 2000/300).
        for ident in self.JOINTS:
            self.write(client, ident, X_TORQUE, 0, 1)
        for ident in range(1, 8):
            drive = self.read(client, ident, X_DRIVE_MODE, 1)
            self.assertEqual(drive, self.DRIVE.get(ident, 0))
            self.write(client, ident, X_DRIVE_MODE, drive + 4, 1)
            self.write(client, ident, X_OPERATING_MODE, POSITION_MODE, 1)
            self.write(client, ident, X_PROFILE_VELOCITY, 2000, 4)
            self.write(client, ident, X_PROFILE_ACCELERATION, 300, 4)
        for ident in self.JOINTS:
            self.write(client, ident, X_TORQUE, 1, 1)
        # The gripper: PWM, its default velocity-based profile (Drive_Mode stays 0).
        self.write(client, 8, X_TORQUE, 0, 1)
        self.assertEqual(self.read(client, 8, X_DRIVE_MODE, 1), 0)
        self.write(client, 8, X_OPERATING_MODE, PWM_MODE, 1)
        self.write(client, 8, X_TORQUE, 1, 1)
        return client

    def joint_positions(self, client: Client, ids) -> dict[int, int]:
        """Joint states: Sync Read of current, velocity and position (and 2 bytes more)."""
        replies = client.sync_read(X_PRESENT_CURRENT, 12, ids)
        return {i: value(self.ok(r)[6:10]) for i, r in replies.items()}

    def test_widowx_250(self):
        client = self.start()
        # The shadows were torqued on with their masters: Torque Enable is RAM, and writes to a
        # Secondary ID reach RAM (docs/bus.md "Secondary (Shadow) ID").
        self.assertEqual(self.read(client, 3, X_TORQUE, 1), 1)
        self.assertEqual(self.read(client, 5, X_TORQUE, 1), 1)
        positions = self.joint_positions(client, [*self.JOINTS, 8])
        # The gripper answers too; torque on in PWM mode it coasts, so its position is not fixed.
        self.assertIn(8, positions)
        del positions[8]
        self.assertEqual(positions, {**dict.fromkeys(self.JOINTS, POWER_ON_POSITION),
                                     6: REVERSED_POWER_ON_POSITION})
        self.assertEqual(self.read(client, 3, X_DRIVE_MODE, 1), 5)
        # A single-joint command (robot_write_joint_command: a Write of Goal_Position to ID 2)
        # reaches the shadow through its Secondary ID; its reverse bit turns it the other way,
        # so both report the goal (docs/motion.md).
        self.write(client, 2, X_GOAL_POSITION, 2300, 4)

        def shadow_follows():
            got = {i: self.read(client, i, X_PRESENT_POSITION, 4) for i in (2, 3)}
            return all(abs(g - 2300) <= 5 for g in got.values()) or got
        self.wait_until(shadow_follows, "shoulder and shadow")
        self.assertEqual(self.read(client, 4, X_PRESENT_POSITION, 4), POWER_ON_POSITION)

    def test_widowx_250_shadow_follows_a_group_sync_write(self):
        """robot_write_commands sends the arm group's goals as one Sync Write to the joints'
        IDs only: a shadow acts on the block of its Secondary ID (docs/bus.md)."""
        client = self.start()
        goals = {i: POWER_ON_POSITION + 200 for i in self.JOINTS}
        goals[6] = REVERSED_POWER_ON_POSITION + 200
        client.sync_write(X_GOAL_POSITION, {i: le(g, 4) for i, g in goals.items()})

        def shadow_follows():
            got = self.joint_positions(client, [2, 3, 4, 5])
            return all(abs(got[i] - goals[{3: 2, 5: 4}.get(i, i)]) <= 5 for i in got) or got
        self.wait_until(shadow_follows, "shadows after the group's Sync Write", seconds=3.0)


class Pypot(RobotBus):
    """pypot's from_config (pypot/robot/config.py: dxl_io_from_confignode scans,
    check_motor_eprom_configuration reads and fixes the EEPROM) with poppy_ergo_jr.json."""

    def test_poppy_ergo_jr(self):
        ids = [1, 2, 3, 4, 5, 6]
        client = self.serve("poppy-ergo-jr", 1_000_000, 2, [(i, "xl-320") for i in ids])
        xl_return_delay, xl_cw_limit, xl_present_position = 5, 6, 37
        for ident in ids:  # scan
            self.assertEqual(value(self.ok(client.ping(ident))[:2]), MODEL["xl-320"])
        for ident in ids:  # get_angle_limit and get_return_delay_time: one Read each
            data = self.ok(client.read(ident, xl_cw_limit, 4))
            self.assertEqual((value(data[:2]), value(data[2:])), (0, 1023))
            self.assertEqual(self.read(client, ident, xl_return_delay, 1), 250)
        # The limits that differ from -150/150 degrees, then Return Delay Time 0, both by Sync
        # Write (degree_to_dxl: 1023 * (150 + deg) / 300, rounded).
        new_limits = {2: (205, 938), 3: (205, 818), 5: (205, 818), 6: (136, 818)}
        client.sync_write(xl_cw_limit, {i: le(cw, 2) + le(ccw, 2)
                                        for i, (cw, ccw) in new_limits.items()})
        client.sync_write(xl_return_delay, {i: b"\x00" for i in ids})
        for ident in ids:
            data = self.ok(client.read(ident, xl_cw_limit, 4))
            self.assertEqual((value(data[:2]), value(data[2:])), new_limits.get(ident, (0, 1023)))
            self.assertEqual(self.read(client, ident, xl_return_delay, 1), 0)
        # The sync loop: present position, speed and load (37, 6 bytes) of every motor.
        replies = client.sync_read(xl_present_position, 6, ids)
        self.assertEqual({i: value(self.ok(r)[:2]) for i, r in replies.items()},
                         dict.fromkeys(ids, 512))


if __name__ == "__main__":
    unittest.main()
