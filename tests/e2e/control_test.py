"""End-to-end tests of the control API (docs/control-api.md): the real dxlemu binary, its
Unix socket and its PTY at once."""
import json
import os
import select
import stat
import subprocess
import tempfile
import time
import unittest

from dxl_client import (Control, Daemon, Port, assert_unanswered, dxlemu_command, heard, packet2,
                        timeout_scale)

PING, READ = 0x01, 0x02
PING_BYTES = len(packet2(1, PING))
BOOT_NS = 400_000_000  # a servo's boot time after power-on (docs/servo.md)
XM430_W350_PING = bytes([0xFC, 0x03, 45])  # model number 1020, firmware 45
SHUTDOWN_MS = 300  # the shutdown scenario's one step


def read_what_is_there(fd):
    """The bytes a pipe holds now, without waiting for more."""
    os.set_blocking(fd, False)
    data = b""
    try:
        while chunk := os.read(fd, 65536):
            data += chunk
    except BlockingIOError:
        pass
    return data


class ControlTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.link = os.path.join(self.dir.name, "dxl0")
        self.socket = os.path.join(self.dir.name, "control.sock")

    def tearDown(self):
        self.dir.cleanup()

    def start(self, *args):
        daemon = Daemon("--link", self.link, "--control", self.socket, *args)
        self.addCleanup(daemon.stop)
        control = Control(daemon.ready["control"])
        self.addCleanup(control.close)
        return daemon, control

    def test_the_readiness_line_names_the_socket_which_only_its_owner_may_use(self):
        daemon, _ = self.start()
        self.assertEqual(daemon.ready["control"], self.socket)
        mode = os.stat(self.socket).st_mode
        self.assertTrue(stat.S_ISSOCK(mode))
        self.assertEqual(stat.S_IMODE(mode), 0o600)

    def test_a_value_set_through_the_api_is_what_the_bus_reads(self):
        # Manual timing: the temperature set stays until the bus reads it (no tick cools it).
        _, control = self.start("--timing", "manual")
        listing = control.call("list")
        self.assertEqual([s["id"] for s in listing["ports"][0]["servos"]], [1, 2, 3])
        control.call("set", port="dxl0", servo=2, item="present_temperature", value=70)
        self.assertEqual(control.call("get", port="dxl0", servo=2, item="present_temperature")["value"], 70)
        port = Port(self.link)
        port.write(packet2(2, READ, bytes([146, 0, 1, 0])))  # Present Temperature
        self.assertEqual(port.status2(), (2, 0, bytes([70])))
        port.close()

    def test_a_blocked_servo_overheats_on_a_stepped_clock_and_the_bus_shows_the_alert(self):
        _, control = self.start("--timing", "manual")
        control.call("set", servo=1, item="shutdown", value=0x04)  # Overheating only
        control.call("set", servo=1, item="torque_enable", value=1)
        control.call("condition.set", servo=1, blocked=True)
        control.call("set", servo=1, item="goal_position", value=3000)
        control.call("clock.step", ms=120000)
        self.assertEqual(control.call("get", servo=1, item="hardware_error_status")["value"], 0x04)
        port = Port(self.link)
        port.write(packet2(1, PING))
        servo_id, error, _ = port.status2()
        self.assertEqual((servo_id, error), (1, 0x80))  # the alert bit
        port.close()

    def test_malformed_requests_get_errors_and_the_connection_stays_up(self):
        started = time.monotonic()  # before the daemon, whose simulated time starts with it
        _, control = self.start()
        other = Control(self.socket)
        self.addCleanup(other.close)
        control.send_line(b"{not json")
        reply = control.reply()
        self.assertEqual((reply["id"], reply["ok"]), (None, False))
        self.assertTrue(reply["error"].startswith("not valid JSON: parse error"), reply)
        reply = control.request("gett")
        self.assertFalse(reply["ok"])
        self.assertTrue(reply["error"].startswith('unknown command "gett" (commands: '), reply)
        reply = control.request("get", servo=9, item="id")
        self.assertEqual((reply["ok"], reply["error"]),
                         (False, "no servo 9 on dxl0 (servos: 1, 2, 3)"))
        reply = control.request("set", servo=1, item="present_temperature", value=300)
        self.assertEqual((reply["ok"], reply["error"]),
                         (False, "value 300 does not fit present_temperature (1 byte)"))
        control.send_line(b"x" * 200000)
        reply = control.reply()
        self.assertEqual((reply["id"], reply["ok"], reply["error"]),
                         (None, False, "request longer than 65536 bytes: discarded"))
        # Still answering, as documented: simulated time since the start, in ns and ms, and the
        # timing; under realtime timing it follows the wall clock, so it is more than 0 (the PTY
        # hand-over measurement alone takes about 20 ms) and no more than the time since `started`.
        now = control.call("clock.now")
        elapsed_ns = (time.monotonic() - started) * 1e9
        self.assertEqual(sorted(now), ["ms", "ns", "timing"])
        self.assertEqual(now["timing"], "realtime")
        self.assertIs(type(now["ns"]), int)
        self.assertGreater(now["ns"], 0)
        self.assertLessEqual(now["ns"], elapsed_ns)
        self.assertAlmostEqual(now["ms"], now["ns"] / 1e6, delta=1e-6)
        self.assertEqual(other.call("get", servo=1, item="id")["value"], 1)

    def assert_ping_unanswered(self, port, control, servo):
        """Pings `servo` and checks the daemon heard the Ping and sent nothing back. Under
        manual timing a reply would have been delivered before `heard` returns."""
        before = control.call("stats", port="dxl0")["dxl0"]
        port.write(packet2(servo, PING))
        after = heard(control, before["bytes_in"] + PING_BYTES)
        self.assertEqual((after["frames"], after["replies"]),
                         (before["frames"] + 1, before["replies"]))
        self.assertIsNone(port.status2(timeout=0.05))

    def test_a_detached_servo_drops_off_the_bus_and_answers_again_once_attached_and_booted(self):
        # Manual timing: the boot time passes only when the test steps the clock.
        _, control = self.start("--timing", "manual")
        port = Port(self.link)
        self.addCleanup(port.close)
        self.assertEqual(control.call("servo.detach", servo=2), {"attached": False, "booting": False})
        self.assert_ping_unanswered(port, control, 2)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2()[0:2], (1, 0))  # the others still answer
        self.assertEqual(control.call("servo.attach", servo=2), {"attached": True, "booting": True})
        self.assert_ping_unanswered(port, control, 2)  # at once: booting
        control.call("clock.step", ms=399)
        self.assert_ping_unanswered(port, control, 2)
        self.assertEqual(control.call("clock.step", ns=999_999)["ns"], BOOT_NS - 1)
        self.assert_ping_unanswered(port, control, 2)  # 1 ns before the boot time ends
        self.assertEqual(control.call("clock.step", ns=1)["ns"], BOOT_NS)
        port.write(packet2(2, PING))
        self.assertEqual(port.status2(), (2, 0, XM430_W350_PING))

    def test_shutdown_stops_the_daemon_and_removes_the_socket_and_the_link(self):
        daemon, control = self.start()
        self.assertTrue(control.request("shutdown")["ok"])
        self.assertEqual(daemon.proc.wait(timeout=5), 0)
        self.assertFalse(os.path.exists(self.socket))
        self.assertFalse(os.path.exists(self.link))


    def test_a_fault_rule_drops_replies_until_it_is_removed(self):
        daemon, control = self.start("--timing", "manual", "--seed", "7")
        self.assertEqual(daemon.ready["seed"], 7)
        rule = control.call("fault.add", rule={"action": "drop_reply",
                                               "match": {"port": "dxl0", "servos": [3]}})
        self.assertEqual(rule, {"rule": 1})
        port = Port(self.link)
        assert_unanswered(control, port, packet2(3, PING))
        port.write(packet2(2, PING))
        self.assertEqual(port.status2()[:2], (2, 0))
        listed = control.call("fault.list")
        self.assertEqual([(r["id"], r["matched"], r["fired"]) for r in listed], [(1, 1, 1)])
        control.call("fault.remove", rule=1)
        port.write(packet2(3, PING))
        self.assertEqual(port.status2()[:2], (3, 0))
        self.assertEqual(control.call("stats", port="dxl0")["dxl0"]["faults_injected"], 1)
        port.close()

    def test_trace_events_reach_the_subscribed_connection_only(self):
        _, control = self.start("--timing", "manual")
        other = Control(self.socket)
        self.addCleanup(other.close)
        self.assertEqual(control.call("trace.subscribe", port="dxl0"), {"ports": ["dxl0"]})
        port = Port(self.link)
        self.addCleanup(port.close)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2()[:2], (1, 0))
        # The Ping and its reply were traced before the reply reached the PTY, so their event
        # lines are on each connection ahead of the reply to any request sent after it: one
        # round trip, and every event due is in hand, with no waiting on the wall clock.
        control.call("clock.now")
        other.call("clock.now")
        events = control.events()
        self.assertEqual([(e["event"], e["dir"], e["port"], e.get("packet")) for e in events],
                         [("trace", "in", "dxl0", "id=1 ping"),
                          ("trace", "out", "dxl0", "id=1 error=0x00 params=FC 03 2D")])
        self.assertEqual(other.events(), [])
        control.call("trace.unsubscribe")
        port.write(packet2(1, PING))
        self.assertEqual(port.status2()[:2], (1, 0))
        control.call("clock.now")
        self.assertEqual(control.events(), [])

    def test_a_scenario_file_runs_its_timeline_from_the_start(self):
        scenario = os.path.join(self.dir.name, "scenario.json")
        with open(scenario, "w", encoding="utf-8") as f:
            json.dump({"steps": [{"at_ms": 0, "cmd": "servo.detach", "port": "dxl0", "servo": 2},
                                 {"at_ms": 300, "cmd": "servo.attach", "port": "dxl0", "servo": 2}]}, f)
        # Manual timing: the steps run when the stepped clock reaches them, to the nanosecond.
        _, control = self.start("--timing", "manual", "--scenario", scenario)
        port = Port(self.link)
        self.addCleanup(port.close)

        def attached():
            return control.call("list")["ports"][0]["servos"][1]["attached"]

        self.assertFalse(attached())  # the step at 0 ms ran before the readiness line
        self.assert_ping_unanswered(port, control, 2)
        control.call("clock.step", ns=300_000_000 - 1)
        self.assertFalse(attached())
        control.call("clock.step", ns=1)
        self.assertTrue(attached())
        # It boots (400 ms from its attach at 300 ms) and answers again.
        control.call("clock.step", ns=BOOT_NS - 1)
        self.assert_ping_unanswered(port, control, 2)
        control.call("clock.step", ns=1)
        port.write(packet2(2, PING))
        self.assertEqual(port.status2(), (2, 0, XM430_W350_PING))

    def write_shutdown_scenario(self):
        scenario = os.path.join(self.dir.name, "stop.json")
        with open(scenario, "w", encoding="utf-8") as f:
            json.dump({"steps": [{"at_ms": SHUTDOWN_MS, "cmd": "shutdown"}]}, f)
        return scenario

    def test_a_scenario_step_runs_on_time_without_any_traffic(self):
        # Manual timing: the step runs when the stepped clock reaches it, to the nanosecond,
        # with nobody on the PTY. The shutdown logs before the reply to the step that ran it,
        # and the daemon serves requests for a moment after it, so what tells "not yet" is its
        # stderr read once the step's reply is in, not whether it still answers.
        daemon, control = self.start("--timing", "manual", "--scenario",
                                     self.write_shutdown_scenario())
        stderr = daemon.proc.stderr.fileno()
        self.assertEqual(control.call("clock.step", ns=SHUTDOWN_MS * 1_000_000 - 1)["ns"],
                         SHUTDOWN_MS * 1_000_000 - 1)
        logged = read_what_is_there(stderr)
        self.assertNotIn(b"stopping", logged)
        self.assertEqual(control.call("stats", port="dxl0")["dxl0"]["bytes_in"], 0)
        self.assertEqual(control.call("clock.step", ns=1)["ns"], SHUTDOWN_MS * 1_000_000)
        self.assertEqual(daemon.proc.wait(timeout=10 * timeout_scale()), 0)
        logged += read_what_is_there(stderr)  # all of it: the daemon has exited
        self.assertIn(b"stopping on the control API's shutdown", logged)
        self.assertFalse(os.path.lexists(self.link))

    def test_in_realtime_a_scenario_step_wakes_the_daemon_without_any_traffic(self):
        # Realtime timing: nothing but the driver's timer can run the step, and not before
        # 300 ms of the wall clock from the daemon's simulated zero, which is at the latest
        # the moment `clock.now` was asked less the time it answers.
        daemon, control = self.start("--scenario", self.write_shutdown_scenario())
        asked = time.monotonic()
        zero = asked - control.call("clock.now")["ns"] / 1e9
        stderr, logged = daemon.proc.stderr.fileno(), b""
        deadline = asked + 10 * timeout_scale()
        while b"stopping" not in logged:
            self.assertTrue(select.select([stderr], [], [], max(0, deadline - time.monotonic()))[0],
                            f"the step did not run: {logged}")
            logged += os.read(stderr, 65536)
        self.assertGreaterEqual(time.monotonic() - zero, SHUTDOWN_MS / 1000)
        self.assertIn(b"stopping on the control API's shutdown", logged)
        self.assertEqual(daemon.proc.wait(timeout=10 * timeout_scale()), 0)

    def test_a_bad_scenario_file_is_refused_naming_file_pointer_and_reason(self):
        scenario = os.path.join(self.dir.name, "bad.json")
        with open(scenario, "w", encoding="utf-8") as f:
            json.dump({"steps": [{"at_ms": 0, "cmd": "fault.add", "rule": {"action": "boom"}}]}, f)
        proc = subprocess.run(dxlemu_command("run", "--link", self.link,
                                              "--control", self.socket, "--scenario", scenario),
                              capture_output=True, text=True, timeout=30)
        self.assertEqual(proc.returncode, 2)
        self.assertIn(scenario, proc.stderr)
        self.assertIn("/steps/0", proc.stderr)
        self.assertIn("rule/action: must be one of drop_reply", proc.stderr)
        self.assertFalse(os.path.exists(self.link))


if __name__ == "__main__":
    unittest.main()
