"""End-to-end: LeRobot's own flows on six FEETECH STS3215 over a real PTY, with the servos as
users find them (docs/feetech.md "LeRobot's flows, tested").

Each test replays what LeRobot's FeetechMotorsBus sends, in LeRobot's order, as
../shared/reference/feetech/README.md "How lerobot drives the bus" describes it, rebuilt on the
repository's own FT-SCS client (python/dxlemu: `Client(protocol="feetech")`, `dxlemu.feetech`'s
sign-magnitude values); neither LeRobot nor FEETECH's SDK is used. `FeetechBus` (lerobot_bus.py,
shared with hands_test.py) holds those call sequences: the connect handshake,
configure_motors(), disable_torque / enable_torque, the half-turn homing, the recording of the
ranges of motion, the calibration written and read back, SYNC READ of Present_Position and SYNC
WRITE of Goal_Position.

1. A kit shipped with Phase bit 4 set (full-angle feedback) on two of its servos: a calibration
   made before configure_motors() (LeRobot's `connect()` calibrates before it configures) fails
   on LeRobot's own check of the homing offset; the calibration made after it (as
   `lerobot-calibrate` does) passes, and what configure_motors() wrote with Lock 0 survives a
   power cycle and a restart with --state, while the same write made locked does not.
2. A calibration whose sweep crosses the 0/4095 seam: the raw reading wraps, the half-turn
   homing makes the same sweep read one contiguous range around 2047.
3. A goal sent with the torque off moves the arm and turns the torque on.
4. Torque on after the arm was moved by hand drives it back to the goal it had (a stale goal);
   writing Goal = Present before torque on keeps it still.

The person who moves the joints is the control API: with the torque off, `set` of
`present_position` turns a shaft by hand to where it reads that value, a small step at a time
(`Hands`: on a single-turn servo the value 4100 is the angle 4, reached the short way, so the
steps cross the seam the way the hand goes, and only the servo wraps what it reads). The daemon
runs under manual timing: replies go out at once, and the servos and the hand move only when the
test steps the clock.
"""
from __future__ import annotations

import json
import os
import tempfile
import unittest
from typing import Iterable, Iterator

from dxl_client import Control, Daemon, timeout_scale
from dxlemu.protocol import FEETECH, Client
from lerobot_bus import FULL_ANGLE, HALF_TURN, LOCK, MAX_RES, RESOLUTION, Calibration, FeetechBus

IDS = [1, 2, 3, 4, 5, 6]
FACTORY_PHASE = 12
SHIPPED_PHASE = FACTORY_PHASE | FULL_ANGLE

BOOT_MS = 1800  # the STS3215's restart time (models/feetech/sts3215.json "boot_ms")
STEP_MS = 20  # how far the clock moves between two looks at moving servos
HAND_STEP = 50  # how far a hand turns a shaft between two of LeRobot's readings
ARRIVED = 3  # steps from a goal that count as there


class Hands:
    """A person turning shafts with the torque off, through the control API: a `set` of
    `present_position` puts the shaft where it reads the value given, then the clock moves on
    a little. A turn is made of steps of at most HAND_STEP, each asking for the reading plus
    the step: on a single-turn servo dxlemu takes a value past 4095 or below 0 as the angle it
    names and moves the shaft the short way to it, the way the hand goes, and the reading that
    comes back wraps, or not, as the servo's feedback does (never the hand's arithmetic)."""

    def __init__(self, control: Control, port_name: str):
        self.control = control
        self.port_name = port_name

    def reading(self, servo: int) -> int:
        return self.control.get(servo, "present_position", port=self.port_name)

    def turn(self, servo: int, steps: int) -> Iterator[None]:
        """Turns `servo` by `steps` encoder steps (positive: towards higher readings), yielding
        after each small step, while LeRobot may read."""
        moved = 0
        while moved != steps:
            step = max(-HAND_STEP, min(HAND_STEP, steps - moved))
            self.control.set(servo, "present_position", self.reading(servo) + step,
                             port=self.port_name)
            self.control.clock_step(ms=STEP_MS)
            moved += step
            yield

    def turn_now(self, servo: int, steps: int) -> None:
        for _ in self.turn(servo, steps):
            pass

    def sweep(self, servo: int, amplitude: int) -> Iterator[None]:
        """Down by `amplitude`, up through the start to `amplitude` above it, back to the start."""
        yield from self.turn(servo, -amplitude)
        yield from self.turn(servo, 2 * amplitude)
        yield from self.turn(servo, -amplitude)

    def sweep_each(self, amplitudes: dict[int, int]) -> Iterator[None]:
        """Each joint through its range in turn, as LeRobot asks ("move all joints
        sequentially through their entire ranges of motion")."""
        for servo, amplitude in amplitudes.items():
            yield from self.sweep(servo, amplitude)


class LeRobotFlow(unittest.TestCase):
    """A daemon under manual timing, a client on its PTY at 1 Mbit/s, the control API, and
    LeRobot's bus and a person's hands on them."""

    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.dir = tmp.name
        self.link = os.path.join(self.dir, "ttyACM0")

    def start(self, *args: str) -> None:
        """Starts `dxlemu run ARGS --timing manual --control ...` and connects to it."""
        control_path = os.path.join(self.dir, "ctl")
        self.daemon = Daemon(*args, "--timing", "manual", "--control", control_path)
        self.addCleanup(self.daemon.stop)
        self.port_name = self.daemon.ready["port"]
        self.control = Control(control_path)
        self.addCleanup(self.control.close)
        self.client = Client(self.daemon.ready["link"], baud=1_000_000, protocol=FEETECH,
                             timeout=0.5 * timeout_scale())
        self.addCleanup(self.client.close)
        self.bus = FeetechBus(self.client, self.control, self.port_name, IDS)
        self.hands = Hands(self.control, self.port_name)

    def start_six(self) -> None:
        """Six STS3215 at IDs 1 ~ 6 as they leave the factory."""
        self.start("--servo", "sts3215:1-6", "--baud", "1000000", "--link", self.link)

    def stop(self) -> None:
        self.client.close()
        self.control.close()
        self.assertEqual(self.daemon.stop(), 0)

    def settle(self, seconds: float = 5.0) -> None:
        """Steps the clock until no servo is moving, for `seconds` of simulated time at most.
        The clock moves first: a move ordered now starts at the servos' next tick."""
        for _ in range(round(seconds * 1000 / STEP_MS)):
            self.control.clock_step(ms=STEP_MS)
            servos = self.control.list()["ports"][0]["servos"]
            if not any(s["moving"] for s in servos):
                return
        self.fail(f"still moving after {seconds} s: {self.bus.sync_read_present()}")

    def wait_until_at(self, goals: dict[int, int], seconds: float = 5.0) -> dict[int, int]:
        """Steps the clock until every servo of `goals` reads within ARRIVED of its goal;
        returns the readings. Fails after `seconds` of simulated time."""
        for _ in range(round(seconds * 1000 / STEP_MS)):
            present = self.bus.sync_read_present()
            if all(abs(present[i] - goal) <= ARRIVED for i, goal in goals.items()):
                return present
            self.control.clock_step(ms=STEP_MS)
        self.fail(f"not at {goals} after {seconds} s: {present}")

    def power_cycle_all(self) -> None:
        """Every servo switched off and on; the clock moves past their restart time."""
        for ident in IDS:
            self.control.power_cycle(ident, port=self.port_name)
        self.control.clock_step(ms=BOOT_MS)


def shipped_kit(link: str, full_angle_ids: Iterable[int]) -> dict:
    """Six STS3215 at 1 Mbit/s as a kit ships them: the servos of `full_angle_ids` with Phase
    bit 4 set at the factory (Phase 28), the others with the factory Phase (12)."""
    full_angle = set(full_angle_ids)
    return {"description": "an SO-101 kit with full-angle feedback on some servos",
            "ports": [{"name": "arm", "link": link, "servos": [
                {"model": "sts3215", "id": ident, "baud": 1_000_000,
                 **({"items": {"phase": SHIPPED_PHASE}} if ident in full_angle else {})}
                for ident in IDS]}]}


class ShippedFullAngleTest(LeRobotFlow):
    """Flow 1: a kit whose servos 2 and 5 ship with Phase bit 4 set."""

    FULL_ANGLE_IDS = (2, 5)
    SHIPPED = dict.fromkeys(IDS, FACTORY_PHASE) | dict.fromkeys(FULL_ANGLE_IDS, SHIPPED_PHASE)
    # Where each joint was when the arm was switched on, and how far the person then moves it
    # to the middle of its range: joints 2 and 5 sit near the encoder's seam (the horn was put
    # on there), and their short move crosses it.
    SWITCHED_ON_AT = {1: 2100, 2: 4000, 3: 1900, 4: 2300, 5: 50, 6: 2000}
    TO_THE_MIDDLE = {1: -40, 2: 150, 3: 60, 4: -120, 5: -150, 6: 30}
    SWEEPS = {1: 900, 2: 1100, 3: 1000, 4: 800, 5: 1500, 6: 500}

    def setUp(self):
        super().setUp()
        self.config = os.path.join(self.dir, "so101.json")
        self.state = os.path.join(self.dir, "state.json")
        with open(self.config, "w", encoding="utf-8") as f:
            json.dump(shipped_kit(self.link, self.FULL_ANGLE_IDS), f)

    def start_kit(self) -> None:
        self.start("--config", self.config, "--state", self.state)

    def switch_on_in_the_arms_pose(self) -> None:
        """The arm as its owner left it: each joint turned to SWITCHED_ON_AT, then the power
        switched on there (Goal_Position takes the reading at power-on)."""
        for ident, reading in self.SWITCHED_ON_AT.items():
            self.hands.turn_now(ident, reading - self.hands.reading(ident))
        self.power_cycle_all()
        self.assertEqual(self.bus.sync_read_present(), self.SWITCHED_ON_AT)

    def move_to_the_middle(self) -> None:
        for ident, steps in self.TO_THE_MIDDLE.items():
            self.hands.turn_now(ident, steps)

    def test_calibration_fails_before_configure_motors_and_passes_after_it(self):
        self.start_kit()
        self.switch_on_in_the_arms_pose()
        bus = self.bus
        self.assertEqual(bus.phases(), self.SHIPPED)

        # Without the fix: LeRobot's robot.connect() on an arm with no calibration file
        # calibrates before it configures, so configure_motors() has not cleared bit 4 yet.
        bus.connect()
        bus.disable_torque()
        bus.set_position_mode()
        self.move_to_the_middle()
        raw = bus.sync_read_raw()
        present = bus.sync_read_present()
        # Full-angle feedback counts the turn the move crossed into: joint 2 reads above 4095,
        # joint 5 below 0 (sign-magnitude: bit 15 set).
        self.assertEqual(present[2], 4150)
        self.assertEqual(present[5], -100)
        self.assertEqual(raw[5], bytes([100, 0x80]))
        for ident in (1, 3, 4, 6):
            self.assertEqual(present[ident],
                             self.SWITCHED_ON_AT[ident] + self.TO_THE_MIDDLE[ident])
        # The half-turn homing of both is out of Homing_Offset's reach: LeRobot raises while
        # writing joint 2's, and calibrate(), and so connect(), never reach configure().
        self.assertEqual({i: h for i, h in bus.half_turn_homings(present).items()
                          if abs(h) > 2047}, {2: 2103, 5: -2147})
        with self.assertRaisesRegex(ValueError, r"^Magnitude 2103 exceeds 2047"):
            bus.set_half_turn_homings()
        self.assertEqual(bus.phases(), self.SHIPPED)

        # With the fix: lerobot-calibrate connects without calibrating, so configure() runs
        # first, its configure_motors() inside torque_disabled (Lock 0) clearing bit 4.
        bus.connect()
        with bus.torque_disabled():
            bus.configure_motors()
            self.assertEqual(bus.phases(), dict.fromkeys(IDS, FACTORY_PHASE))
            # Single-turn at once: the same shafts read within one turn.
            present = bus.sync_read_present()
            self.assertEqual((present[2], present[5]), (4150 - RESOLUTION, RESOLUTION - 100))
            bus.set_position_mode()
        # configure() ends with enable_torque: the servos drive to the goal they have had
        # since power-on, the pose they were switched on in.
        self.settle()
        self.assertEqual(bus.sync_read_present(), self.SWITCHED_ON_AT)

        # calibrate(): torque off, the person moves the arm to the middle again.
        bus.disable_torque()
        bus.set_position_mode()
        self.move_to_the_middle()
        homings = bus.set_half_turn_homings()
        self.assertEqual(homings[2], 4150 - RESOLUTION - HALF_TURN)  # -1993
        self.assertEqual(homings[5], RESOLUTION - 100 - HALF_TURN)  # 1949
        self.assertTrue(all(abs(h) <= 2047 for h in homings.values()), homings)
        self.assertEqual(bus.sync_read_present(), dict.fromkeys(IDS, HALF_TURN))
        ranges = bus.record_ranges_of_motion(self.hands.sweep_each(self.SWEEPS))
        for ident, amplitude in self.SWEEPS.items():
            self.assertEqual((ranges.mins[ident], ranges.maxes[ident]),
                             (HALF_TURN - amplitude, HALF_TURN + amplitude), f"motor {ident}")
            self.assertTrue(0 <= ranges.mins[ident] < HALF_TURN < ranges.maxes[ident] <= MAX_RES)
        calibration = {i: Calibration(homings[i], ranges.mins[i], ranges.maxes[i]) for i in IDS}
        bus.write_calibration(calibration)
        self.assertEqual(bus.read_calibration(), calibration)
        bus.disable_torque()  # lerobot-calibrate's disconnect()

        # Written with Lock 0: Phase and the calibration survive a power cycle...
        self.power_cycle_all()
        self.assertEqual(bus.phases(), dict.fromkeys(IDS, FACTORY_PHASE))
        self.assertEqual(bus.read_calibration(), calibration)
        self.assertEqual(bus.sync_read_present(), dict.fromkeys(IDS, HALF_TURN))
        # ... and a restart of dxlemu with --state, though the config still says Phase 28.
        self.stop()
        self.start_kit()
        self.assertEqual(self.bus.phases(), dict.fromkeys(IDS, FACTORY_PHASE))
        self.assertEqual(self.bus.read_calibration(), calibration)

    def test_phase_cleared_while_locked_comes_back_at_power_on(self):
        # configure_motors() called outside torque_disabled: Lock is still 1 from power-on, so
        # the Phase write is in effect at once and forgotten at power-off.
        self.start_kit()
        self.bus.connect()
        self.assertEqual(self.bus.read(2, LOCK, 1), 1)
        self.bus.configure_motors()
        self.assertEqual(self.bus.phases(), dict.fromkeys(IDS, FACTORY_PHASE))
        self.power_cycle_all()
        self.assertEqual(self.bus.phases(), self.SHIPPED)
        # The same after a restart with --state: nothing written locked was saved.
        self.bus.configure_motors()
        self.stop()
        with open(self.state, encoding="utf-8") as f:
            saved = json.load(f)["ports"]["arm"]
        self.assertEqual([s["eeprom"]["phase"] for s in saved], list(self.SHIPPED.values()))
        self.start_kit()
        self.assertEqual(self.bus.phases(), self.SHIPPED)


class SeamCrossingCalibrationTest(LeRobotFlow):
    """Flow 2: a joint whose middle sits near the encoder's 0/4095 seam."""

    JOINT = 3
    MIDDLE = 4000  # where joint 3 reads in the middle of its range, before any homing
    AMPLITUDE = 600  # its range: 600 steps either side of the middle
    OTHERS = {1: 700, 2: 800, 4: 500, 5: 1000, 6: 400}

    def test_half_turn_homing_makes_a_sweep_across_the_seam_contiguous(self):
        self.start_six()
        bus = self.bus
        bus.connect()
        # calibrate(): torque off; the person puts joint 3 in the middle of its range.
        bus.disable_torque()
        bus.set_position_mode()
        self.hands.turn_now(self.JOINT, self.MIDDLE - self.hands.reading(self.JOINT))

        # Before the homing write (Homing_Offset 0, as reset_calibration leaves it) the sweep
        # of joint 3 crosses the seam: its reading jumps from 4050 to 4 and back.
        bus.reset_calibration()
        raw = bus.record_ranges_of_motion(self.hands.sweep(self.JOINT, self.AMPLITUDE),
                                          [self.JOINT])
        path = [r[self.JOINT] for r in raw.readings]
        jumps = [(a, b) for a, b in zip(path, path[1:]) if abs(b - a) > RESOLUTION // 2]
        self.assertEqual(jumps, [(4050, 4), (4, 4050)])
        # The range it records spans the whole turn though the joint moved 1200 steps, and the
        # joint's middle is not inside it as a range of 0 ~ 4095 would need.
        self.assertEqual((raw.mins[self.JOINT], raw.maxes[self.JOINT]), (4, 4050))

        # set_half_turn_homings: the middle reads 2047; the same sweep is one contiguous range.
        homings = bus.set_half_turn_homings()
        self.assertEqual(homings[self.JOINT], self.MIDDLE - HALF_TURN)
        self.assertEqual(bus.sync_read_present()[self.JOINT], HALF_TURN)
        ranges = bus.record_ranges_of_motion(
            self.hands.sweep_each({self.JOINT: self.AMPLITUDE, **self.OTHERS}))
        path = [r[self.JOINT] for r in ranges.readings]
        self.assertLessEqual(max(abs(b - a) for a, b in zip(path, path[1:])), HAND_STEP)
        low, high = ranges.mins[self.JOINT], ranges.maxes[self.JOINT]
        self.assertEqual((low, high), (HALF_TURN - self.AMPLITUDE, HALF_TURN + self.AMPLITUDE))
        for ident in IDS:
            self.assertTrue(0 <= ranges.mins[ident] < HALF_TURN < ranges.maxes[ident] <= MAX_RES,
                            (ident, ranges.mins[ident], ranges.maxes[ident]))
        calibration = {i: Calibration(homings[i], ranges.mins[i], ranges.maxes[i]) for i in IDS}
        bus.write_calibration(calibration)
        self.assertEqual(bus.read_calibration(), calibration)

        # The limits hold: a goal past the maximum stops joint 3 there. Goal = Present first,
        # so that torque on holds the arm where it is (test 4).
        bus.sync_write_goal(bus.sync_read_present())
        bus.enable_torque()
        bus.sync_write_goal({self.JOINT: high + 500})
        self.wait_until_at({self.JOINT: high})
        self.settle()
        self.assertEqual(bus.sync_read_present()[self.JOINT], high)


class GoalWithTorqueOffTest(LeRobotFlow):
    """Flow 3: LeRobot's sync_write of Goal_Position to an arm whose torque is off."""

    def test_a_goal_sent_with_the_torque_off_moves_the_arm(self):
        self.start_six()
        bus = self.bus
        bus.connect()
        bus.disable_torque()
        self.assertEqual(bus.torques(), dict.fromkeys(IDS, 0))
        start = bus.sync_read_present()
        goals = {ident: 1000 + 300 * ident for ident in IDS}
        bus.sync_write_goal(goals)
        # The goal turned the torque on, on every servo it reached.
        self.assertEqual(bus.torques(), dict.fromkeys(IDS, 1))
        present = self.wait_until_at(goals)
        self.assertTrue(all(abs(present[i] - start[i]) > 100 for i in IDS), (start, present))
        self.assertEqual(bus.torques(), dict.fromkeys(IDS, 1))


class StaleGoalTest(LeRobotFlow):
    """Flow 4: torque on after the arm was moved by hand with the torque off."""

    GOALS = {ident: 2300 + 100 * ident for ident in IDS}  # the last goal sent
    BY_HAND = {1: -700, 2: 500, 3: -400, 4: 900, 5: -300, 6: 600}

    def move_then_let_go(self) -> dict[int, int]:
        """The arm at GOALS under torque; torque off; the person moves it by BY_HAND."""
        self.bus.disable_torque()
        for ident, steps in self.BY_HAND.items():
            self.hands.turn_now(ident, steps)
        moved = self.bus.sync_read_present()
        self.assertEqual(moved, {i: self.GOALS[i] + self.BY_HAND[i] for i in IDS})
        return moved

    def test_torque_on_drives_to_the_stale_goal_and_goal_equals_present_keeps_it_still(self):
        self.start_six()
        bus = self.bus
        bus.connect()
        bus.enable_torque()
        bus.sync_write_goal(self.GOALS)
        self.wait_until_at(self.GOALS)
        self.settle()

        # enable_torque alone: every joint drives back to the goal it had.
        self.move_then_let_go()
        bus.enable_torque()
        self.wait_until_at(self.GOALS)

        # Goal = Present first: the write itself turns the torque on (test 3), towards where
        # the arm already is, and enable_torque afterwards moves nothing.
        self.settle()
        moved = self.move_then_let_go()
        bus.sync_write_goal(bus.sync_read_present())
        self.assertEqual(bus.torques(), dict.fromkeys(IDS, 1))
        bus.enable_torque()
        for _ in range(2000 // STEP_MS):  # two seconds, looking every step
            self.control.clock_step(ms=STEP_MS)
            present = bus.sync_read_present()
            self.assertTrue(all(abs(present[i] - moved[i]) <= 1 for i in IDS), (moved, present))


if __name__ == "__main__":
    unittest.main()
