"""End-to-end: a leader and a follower served by one daemon (docs/robots.md "Several robots in
one daemon"): `dxlemu run --robot so101-leader --robot so101-follower` over real PTYs, each port
named by its robot, each answering on its own link, neither hearing the other; with
`--physics so101-follower` after the follower, the follower's servos drive the MuJoCo arm and
the leader's do not. `dxlemu robots` lists the pair with that command.

The profiles are served from copies whose links lie in the test's own directory (a profile of
`--robots DIR` replaces the shipped one of its name), so that no daemon of another test or of
the user meets these links in /tmp. The physics tests need a build with MuJoCo
($DXLEMU_HAVE_MUJOCO=1, set by tests/CMakeLists.txt); without it, the daemon's refusal of the
physics file is what is checked.
"""
import json
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

from dxl_client import Control, DaemonProcess, dxlemu_command, timeout_scale
from dxlemu.protocol import FEETECH, Client

ROBOTS = Path(__file__).resolve().parents[2] / "robots"
HAVE_MUJOCO = os.environ.get("DXLEMU_HAVE_MUJOCO") == "1"
PAIR = ("so101-leader", "so101-follower")
IDS = [1, 2, 3, 4, 5, 6]
# STS3215 items (models/feetech/sts3215.json).
GOAL_POSITION, PRESENT_POSITION = 42, 56
POWER_ON_POSITION = 2048
GOAL = 1000  # a Goal_Position no servo holds at power-on


class PairTest(unittest.TestCase):
    """The SO-101 leader and follower, their profiles copied with links in a directory of the
    test's own."""

    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.dir = Path(tmp.name)
        self.robots = self.dir / "robots"
        self.robots.mkdir()
        self.links = {}
        for name in PAIR:
            profile = json.loads((ROBOTS / f"{name}.json").read_text())
            self.links[name] = str(self.dir / name)
            profile["ports"][0]["link"] = self.links[name]
            (self.robots / f"{name}.json").write_text(json.dumps(profile))

    def serve(self, *args: str) -> tuple[list[dict], Control]:
        """`dxlemu run --robots DIR ARGS` once both ports are ready: their readiness lines and a
        control connection."""
        daemon = DaemonProcess(["--robots", str(self.robots), *args,
                                "--control", str(self.dir / "control.sock")], ports=2)
        self.addCleanup(daemon.stop)
        control = Control(daemon.ready[0]["control"])
        self.addCleanup(control.close)
        return daemon.ready, control

    def client(self, robot: str) -> Client:
        """A FEETECH client at 1 Mbit/s on `robot`'s link."""
        client = Client(self.links[robot], baud=1_000_000, protocol=FEETECH,
                        timeout=0.5 * timeout_scale())
        self.addCleanup(client.close)
        return client

    def read(self, client: Client, ident: int, address: int) -> int:
        reply = client.read(ident, address, 2)
        self.assertEqual(reply.error, 0)
        return int.from_bytes(reply.data, "little")


class TwoRobots(PairTest):
    def test_both_arms_are_served_each_on_its_own_port_and_link(self):
        ready, control = self.serve("--robot", "so101-leader", "--robot", "so101-follower",
                                    "--timing", "fast")
        # One readiness line per robot, in command-line order, each port named by its robot.
        self.assertEqual([line["port"] for line in ready], list(PAIR))
        self.assertEqual([line["link"] for line in ready], [self.links[n] for n in PAIR])
        for line in ready:
            self.assertEqual([(s["id"], s["model"]) for s in line["servos"]],
                             [(i, "sts3215") for i in IDS])
        self.assertEqual(sorted(control.stats()), sorted(PAIR))
        leader, follower = self.client("so101-leader"), self.client("so101-follower")
        for client in (leader, follower):
            self.assertEqual(client.ping(1).error, 0)
        # A write to the leader's servo 1 changes that servo only: the follower's 1 is another.
        before = self.read(follower, 1, GOAL_POSITION)
        self.assertNotEqual(before, GOAL)
        self.assertEqual(leader.write_int(1, GOAL_POSITION, GOAL, 2).error, 0)
        self.assertEqual(self.read(leader, 1, GOAL_POSITION), GOAL)
        self.assertEqual(self.read(follower, 1, GOAL_POSITION), before)
        self.assertEqual(control.get(1, "goal_position", port="so101-leader"), GOAL)
        self.assertEqual(control.get(1, "goal_position", port="so101-follower"), before)

    def test_robots_lists_the_pair_with_the_command_that_serves_both(self):
        result = subprocess.run(dxlemu_command("robots"), capture_output=True, text=True,
                                timeout=30)
        self.assertEqual(result.returncode, 0, result.stderr)
        lines = result.stdout.splitlines()
        self.assertIn("so101-leader + so101-follower: dxlemu run --robot so101-leader "
                      "--robot so101-follower", lines)
        self.assertIn("koch-v1.1-leader + koch-v1.1-follower: dxlemu run --robot "
                      "koch-v1.1-leader --robot koch-v1.1-follower", lines)
        leader = next(line for line in lines if line.startswith("so101-leader "))
        self.assertIn(" leader of so101-follower ", leader)


class PhysicsOnOne(PairTest):
    @unittest.skipUnless(HAVE_MUJOCO, "this build has no MuJoCo")
    def test_the_follower_drives_the_arm_and_the_leader_stays_put(self):
        _, control = self.serve("--robot", "so101-leader", "--robot", "so101-follower",
                                "--physics", "so101-follower", "--timing", "manual")
        joints = control.physics()["joints"]
        self.assertEqual([(j["port"], j["servo"]) for j in joints],
                         [("so101-follower", i) for i in IDS])
        # Torque off for a second: gravity moves the follower's arm, its servos read it; nothing
        # moves the leader's.
        control.clock_step(ms=1000)
        moved = {j["joint"]: j["position_rad"] for j in control.physics()["joints"]
                 if abs(j["position_rad"]) > 0.05}
        self.assertTrue(moved, "no joint of the follower moved under gravity")
        leader, follower = self.client("so101-leader"), self.client("so101-follower")
        present = {i: self.read(follower, i, PRESENT_POSITION) for i in IDS}
        self.assertNotEqual(present, dict.fromkeys(IDS, POWER_ON_POSITION))
        self.assertEqual({i: self.read(leader, i, PRESENT_POSITION) for i in IDS},
                         dict.fromkeys(IDS, POWER_ON_POSITION))

    @unittest.skipIf(HAVE_MUJOCO, "this build has MuJoCo")
    def test_without_mujoco_the_physics_file_is_refused(self):
        result = subprocess.run(
            dxlemu_command("run", "--robots", str(self.robots), "--robot", "so101-leader",
                           "--robot", "so101-follower", "--physics", "so101-follower"),
            capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 2)
        self.assertIn("so101-follower.json: /: this build of dxlemu has no MuJoCo", result.stderr)

    def test_physics_before_the_robots_is_refused(self):
        result = subprocess.run(
            dxlemu_command("run", "--physics", "so101-follower", "--robot", "so101-leader",
                           "--robot", "so101-follower"),
            capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 2)
        self.assertIn("--physics: given before the first --robot, with 2 robots: put it after "
                      "the --robot it is for", result.stderr)


if __name__ == "__main__":
    unittest.main()
