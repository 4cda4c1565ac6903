"""End-to-end tests of `dxlemu ctl` (docs/control-api.md "From a shell: dxlemu ctl"): the real
binary as a shell command against a real daemon's control socket."""
import json
import os
import socket
import subprocess
import tempfile
import unittest
from unittest import mock

from dxl_client import Daemon, dxlemu_command


def ctl(*args, env=None):
    """`dxlemu ctl ARGS`: (exit status, stdout, stderr). DXLEMU_CONTROL is unset unless `env`
    sets it, so that the test's own environment cannot choose the socket."""
    environment = {k: v for k, v in os.environ.items() if k != "DXLEMU_CONTROL"}
    environment.update(env or {})
    result = subprocess.run(dxlemu_command("ctl", *args), capture_output=True, text=True,
                            timeout=30, env=environment)
    return result.returncode, result.stdout, result.stderr


class CtlTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.link = os.path.join(self.dir.name, "dxl0")
        self.socket = os.path.join(self.dir.name, "control.sock")

    def start(self, *args):
        daemon = Daemon("--link", self.link, *args)
        self.addCleanup(daemon.stop)
        return daemon

    def ok(self, *args, env=None):
        """The printed result of a command that must succeed, parsed."""
        code, out, err = ctl(*args, env=env)
        self.assertEqual((code, err), (0, ""), out)
        return json.loads(out)

    def test_list_get_and_set_print_the_result_as_json(self):
        # Manual timing: the temperature set below must not cool down before it is read back,
        # however long `dxlemu ctl` takes to start (seconds under scripts/memcheck.sh).
        self.start("--control", self.socket, "--timing", "manual")
        listing = self.ok("--control", self.socket, "list")
        self.assertEqual([s["id"] for s in listing["ports"][0]["servos"]], [1, 2, 3])
        self.assertEqual(self.ok("--control", self.socket, "get", "servo=1", "item=id"),
                         {"item": "id", "value": 1})
        self.assertEqual(self.ok("--control", self.socket, "set", "port=dxl0", "servo=2",
                                 "item=present_temperature", "value=70"),
                         {"item": "present_temperature", "value": 70})
        self.assertEqual(self.ok("--control", self.socket, "get", '{"servo": 2}',
                                 "item=present_temperature")["value"], 70)
        code, out, _ = ctl("--control", self.socket, "get", "servo=1", "item=id")
        self.assertEqual(out, '{\n  "item": "id",\n  "value": 1\n}\n')  # indented, in order

    def test_help_names_the_commands(self):
        self.start("--control", self.socket)
        commands = self.ok("--control", self.socket, "help")
        self.assertTrue({"list", "get", "set", "clock.step", "stats", "shutdown"} <= set(commands))

    def test_a_refused_request_prints_the_error_and_exits_1(self):
        self.start("--control", self.socket)
        code, out, err = ctl("--control", self.socket, "gett")
        self.assertEqual((code, out), (1, ""))
        self.assertTrue(err.startswith('dxlemu ctl: unknown command "gett" (commands: '), err)
        code, _, err = ctl("--control", self.socket, "get", "servo=9", "item=id")
        self.assertEqual((code, err), (1, "dxlemu ctl: no servo 9 on dxl0 (servos: 1, 2, 3)\n"))

    def test_a_bad_argument_is_refused_before_connecting_with_exit_2(self):
        code, out, err = ctl("--control", self.socket, "get", "servo")
        self.assertEqual((code, out), (2, ""))
        self.assertEqual(err, 'dxlemu ctl: argument "servo": expected key=value or a JSON object\n')

    def test_a_missing_socket_is_named_with_exit_2(self):
        missing = os.path.join(self.dir.name, "nobody.sock")
        code, out, err = ctl("--control", missing, "list")
        self.assertEqual((code, out), (2, ""))
        self.assertIn("cannot connect to the control socket " + missing, err)

    def test_without_control_it_takes_dxlemu_control_then_the_only_live_socket(self):
        runtime = os.path.join(self.dir.name, "runtime")
        os.mkdir(runtime)
        env = {"XDG_RUNTIME_DIR": runtime}
        code, _, err = ctl("list", env=env)
        self.assertEqual(code, 2)
        self.assertIn("no running dxlemu found: no live control socket " + runtime +
                      "/dxlemu-*.sock; pass --control PATH", err)
        # A stale socket file is not a running daemon.
        stale = os.path.join(runtime, "dxlemu-1.sock")
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
            s.bind(stale)
        with mock.patch.dict(os.environ, env):
            daemon = self.start()
        self.assertEqual(os.path.dirname(daemon.ready["control"]), runtime)
        self.assertEqual(self.ok("get", "servo=3", "item=id", env=env)["value"], 3)
        self.assertEqual(self.ok("get", "servo=3", "item=id",
                                 env={"DXLEMU_CONTROL": daemon.ready["control"]})["value"], 3)
        with mock.patch.dict(os.environ, env):
            other = Daemon("--link", os.path.join(self.dir.name, "dxl1"))
        self.addCleanup(other.stop)
        code, _, err = ctl("list", env=env)
        self.assertEqual(code, 2)
        self.assertIn("several running dxlemu found (", err)
        self.assertIn(daemon.ready["control"], err)
        self.assertIn(other.ready["control"], err)
        self.assertNotIn(stale, err)

    def test_shutdown_stops_the_daemon(self):
        daemon = self.start("--control", self.socket)
        self.assertEqual(self.ok("--control", self.socket, "shutdown"), {})
        self.assertEqual(daemon.proc.wait(timeout=5), 0)


if __name__ == "__main__":
    unittest.main()
