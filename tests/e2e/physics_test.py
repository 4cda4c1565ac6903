"""End-to-end tests of physics (docs/physics.md): the real dxlemu binary with the shipped
pendulum config, read over its PTY in Protocol 2.0 while the control API steps a manual clock.
Needs a build with MuJoCo ($DXLEMU_HAVE_MUJOCO=1, set by tests/CMakeLists.txt); without it the
daemon's refusal of the config is what is checked."""
import json
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

from dxl_client import Control, Daemon, Port, dxlemu_command, packet2

READ, WRITE = 0x02, 0x03
EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples" / "physics"
HAVE_MUJOCO = os.environ.get("DXLEMU_HAVE_MUJOCO") == "1"
# XM430-W350 items (models/xm430-w350.json).
TORQUE_ENABLE, GOAL_POSITION = 64, 116
PRESENT_CURRENT, PRESENT_POSITION = 126, 132
LEVEL = 2048  # Present Position with the link level (zero_offset_deg 180)
STOP = LEVEL + 683  # the hinge's stop at +60 degrees


def signed(data: bytes) -> int:
    return int.from_bytes(data, "little", signed=True)


class PhysicsTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "arm")
        config = json.loads((EXAMPLES / "pendulum.json").read_text())
        config["ports"][0]["link"] = self.link
        config["physics"]["mjcf"] = str(EXAMPLES / "pendulum.xml")
        self.config = os.path.join(self.dir.name, "pendulum.json")
        with open(self.config, "w") as f:
            json.dump(config, f)

    def serve(self, *args: str) -> tuple[Control, Port]:
        """The daemon serving `args` under manual timing, its control connection and its PTY."""
        daemon = Daemon(*args, "--timing", "manual",
                        "--control", os.path.join(self.dir.name, "control.sock"))
        self.addCleanup(daemon.stop)
        control = Control(daemon.ready["control"])
        self.addCleanup(control.close)
        port = Port(self.link)
        self.addCleanup(port.close)
        return control, port

    @unittest.skipUnless(HAVE_MUJOCO, "this build has no MuJoCo")
    def test_the_pendulum_falls_onto_its_stop_and_the_servo_lifts_and_holds_it(self):
        control, port = self.serve("--config", self.config)

        def read(address: int, size: int) -> int:
            port.write(packet2(1, READ, bytes([address, 0, size, 0])))
            servo, error, data = port.status2()
            self.assertEqual((servo, error), (1, 0))
            return signed(data)

        def write(address: int, value: int, size: int):
            port.write(packet2(1, WRITE, bytes([address, 0]) + value.to_bytes(size, "little")))
            self.assertEqual(port.status2(), (1, 0, b""))

        self.assertEqual(read(PRESENT_POSITION, 4), LEVEL)
        control.call("clock.step", ms=1000)  # torque off: it falls
        self.assertLessEqual(abs(read(PRESENT_POSITION, 4) - STOP), 10)
        self.assertEqual(read(PRESENT_CURRENT, 2), 0)
        write(TORQUE_ENABLE, 1, 1)
        write(GOAL_POSITION, LEVEL, 4)
        control.call("clock.step", ms=3000)
        self.assertLessEqual(abs(read(PRESENT_POSITION, 4) - LEVEL), 16)
        # m*g*l over the torque constant: 0.4905 N.m / (4.1 / 2.3 N.m/A) in 2.69 mA units.
        self.assertLessEqual(abs(read(PRESENT_CURRENT, 2) - (-102.3)), 2)

    def physics_file(self) -> str:
        """The shipped pendulum as a physics file for --physics, on servo 1 of port dxl0."""
        path = os.path.join(self.dir.name, "pendulum-physics.json")
        with open(path, "w") as f:
            json.dump({"mjcf": str(EXAMPLES / "pendulum.xml"),
                       "joints": [{"port": "dxl0", "id": 1, "joint": "shoulder",
                                   "zero_offset_deg": 180}]}, f)
        return path

    @unittest.skipUnless(HAVE_MUJOCO, "this build has no MuJoCo")
    def test_a_physics_file_attached_to_servos_and_a_push_through_the_control_api(self):
        control, port = self.serve("--servo", "xm430-w350:1", "--link", self.link,
                                   "--physics", self.physics_file())

        def position() -> int:
            port.write(packet2(1, READ, bytes([PRESENT_POSITION, 0, 4, 0])))
            servo, error, data = port.status2()
            self.assertEqual((servo, error), (1, 0))
            return signed(data)

        control.call("clock.step", ms=1000)  # torque off: onto the +60 degree stop
        joint = control.call("physics", joint="shoulder")
        self.assertEqual((joint["port"], joint["servo"]), ("dxl0", 1))
        self.assertAlmostEqual(joint["position_rad"], 1.0472, delta=0.02)
        self.assertLessEqual(abs(position() - STOP), 10)
        # A push stronger than gravity lifts the link onto the other stop; the shaft follows.
        pushed = control.call("physics.apply", joint="shoulder", torque_nm=-1)
        self.assertEqual(pushed["external_torque_nm"], -1)
        control.call("clock.step", ms=1000)
        self.assertLessEqual(abs(position() - (LEVEL - 683)), 10)
        with self.assertRaisesRegex(Exception, 'no hinge or slide joint "elbow"'):
            control.call("physics.apply", joint="elbow", torque_nm=1)
        self.assertEqual(control.call("physics")["joints"][0]["external_torque_nm"], -1)

    def test_check_with_a_physics_file_names_it_when_refused(self):
        plain = os.path.join(self.dir.name, "plain.json")
        with open(plain, "w") as f:
            json.dump({"ports": [{"name": "dxl0", "servos": [{"model": "xm430-w350", "id": 1}]}]},
                      f)
        physics = self.physics_file()
        self.check_world(["--physics", physics, plain],
                         physics + ": /: this build of dxlemu has no MuJoCo")
        # A config with physics of its own refuses another (without MuJoCo, its own already).
        result = subprocess.run(dxlemu_command("check", self.config, "--physics", physics),
                                capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 2)
        self.assertIn("--physics: the config has a \"physics\" of its own" if HAVE_MUJOCO
                      else self.config + ": /physics: this build of dxlemu has no MuJoCo",
                      result.stderr)

    def test_check_loads_the_world_or_refuses_it_without_mujoco(self):
        self.check_world([self.config],
                         self.config + ": /physics: this build of dxlemu has no MuJoCo")

    def check_world(self, args: list[str], refusal: str) -> None:
        """`dxlemu check ARGS` loads the pendulum's world, or (without MuJoCo) refuses with
        `refusal`."""
        result = subprocess.run(dxlemu_command("check", *args), capture_output=True, text=True,
                                timeout=30)
        if HAVE_MUJOCO:
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("physics: " + str(EXAMPLES / "pendulum.xml") + ", 1 joint",
                          result.stdout)
        else:
            self.assertEqual(result.returncode, 2)
            self.assertIn(refusal, result.stderr)


if __name__ == "__main__":
    unittest.main()
