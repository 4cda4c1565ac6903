"""End-to-end tests: the real dxlemu binary, driven over its pseudo-terminal (docs/testing.md).

Tests run the daemon under manual timing, whose replies go out at once and are never dropped as
late, unless the wall clock is their subject (reply time in realtime, a move followed in real
time, a packet split by a sleep, what fast timing follows); their timing assertions are lower
bounds and generous upper ones: these machines are shared and noisy.
"""
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest
from pathlib import Path
from unittest import mock

from dxl_client import (Control, Daemon, Port, assert_unanswered, dxlemu_command, heard, packet1,
                        packet2)

PING, READ, WRITE, SYNC_READ = 0x01, 0x02, 0x03, 0x82
XM430_W350_PING = bytes([0xFC, 0x03, 45])  # model number 1020, firmware 45 (models/xm430-w350.json)


class DaemonTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.link = os.path.join(self.dir.name, "dxl0")

    def tearDown(self):
        self.dir.cleanup()

    def start(self, *args):
        daemon = Daemon("--link", self.link, *args)
        self.addCleanup(daemon.stop)
        return daemon

    def start_manual(self, *args):
        """The daemon under manual timing, and a control connection to it."""
        control_path = os.path.join(self.dir.name, "control.sock")
        daemon = self.start("--timing", "manual", "--control", control_path, *args)
        control = Control(control_path)
        self.addCleanup(control.close)
        return daemon, control

    def test_readiness_line_names_the_port_the_pty_the_link_and_the_servos(self):
        ready = self.start().ready
        self.assertEqual(ready["event"], "ready")
        self.assertEqual(ready["port"], "dxl0")
        self.assertTrue(ready["pty"].startswith("/dev/pts/"))
        self.assertEqual(ready["link"], self.link)
        self.assertEqual(os.path.realpath(self.link), ready["pty"])
        self.assertEqual(ready["servos"], [{"id": i, "model": "xm430-w350"} for i in (1, 2, 3)])

    def test_ping_read_and_write_in_protocol_2(self):
        self.start_manual()
        port = Port(self.link)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2(), (1, 0, XM430_W350_PING))
        port.write(packet2(2, WRITE, bytes([116, 0, 0x00, 0x02, 0x00, 0x00])))  # Goal Position 512
        self.assertEqual(port.status2(), (2, 0, b""))
        port.write(packet2(2, READ, bytes([116, 0, 4, 0])))
        self.assertEqual(port.status2(), (2, 0, bytes([0x00, 0x02, 0x00, 0x00])))
        port.close()

    def test_a_goal_moves_the_servo_in_real_time_along_its_profile(self):
        # Realtime timing is the subject; a reply the loaded machine made late is still one the
        # test waits for, so none is dropped.
        self.start("--servo", "xm430-w350:1", "--late-reply-limit-ms", "0")
        port = Port(self.link)

        def write(address, value, size):
            port.write(packet2(1, WRITE, bytes([address, 0]) + value.to_bytes(size, "little", signed=True)))
            self.assertEqual(port.status2(), (1, 0, b""))

        def read(address, size):
            port.write(packet2(1, READ, bytes([address, 0, size, 0])))
            servo_id, error, data = port.status2()
            self.assertEqual((servo_id, error), (1, 0))
            return int.from_bytes(data, "little", signed=True)

        start = read(132, 4)  # Present Position
        write(112, 200, 4)  # Profile Velocity: 200 x 0.229 rev/min = 3.1 pulses/ms
        write(108, 50, 4)  # Profile Acceleration: t1 = 64 x 200 / 50 = 256 ms
        write(64, 1, 1)  # Torque Enable
        write(116, start + 1000, 4)  # Goal Position
        began = time.monotonic()
        seen_moving = False
        while read(132, 4) != start + 1000:
            seen_moving = seen_moving or read(122, 1) == 1  # Moving
            self.assertLess(time.monotonic() - began, 10, "the servo never arrived")
        elapsed = time.monotonic() - began
        self.assertTrue(seen_moving)
        self.assertGreater(elapsed, 0.5)  # t3 = t1 + 64 x 1000 / 200 = 576 ms modelled
        while read(122, 1) != 0:  # Moving clears at the tick after the last step
            self.assertLess(time.monotonic() - began, 10, "the servo never stopped")
        self.assertEqual(read(123, 1) & 0x01, 0x01)  # Moving Status: in position
        port.close()

    def test_protocol_1_servo_at_1_mbps_on_a_mixed_bus(self):
        _, control = self.start_manual("--servo", "xm430-w350:1", "--servo", "ax-12a:5")
        port = Port(self.link, 1000000)  # AX-12A factory rate; the XM430 hears noise
        port.write(packet1(5, PING))
        self.assertEqual(port.status1(), (5, 0, b""))
        port.write(packet1(5, READ, bytes([0, 2])))  # Model Number
        self.assertEqual(port.status1(), (5, 0, bytes([12, 0])))
        assert_unanswered(control, port, packet2(1, PING))
        port.close()

    def test_broadcast_ping_and_sync_read_answer_in_order(self):
        self.start_manual()
        port = Port(self.link)
        port.write(packet2(0xFE, PING))
        self.assertEqual([port.status2()[0] for _ in range(3)], [1, 2, 3])
        port.write(packet2(0xFE, SYNC_READ, bytes([7, 0, 1, 0, 3, 1, 2])))  # ID, in order 3 1 2
        self.assertEqual([port.status2() for _ in range(3)],
                         [(3, 0, b"\x03"), (1, 0, b"\x01"), (2, 0, b"\x02")])
        port.close()

    def test_a_packet_split_across_writes_is_one_packet_up_to_the_inter_byte_timeout(self):
        # Manual timing: the daemon stamps the client's bytes with simulated time, which stands
        # still between the two writes unless the test steps it. The halves are one packet when
        # the gap is at most the protocol's inter-byte timeout (2.0: 1.5 ms, 1.0: 100 ms; a gap
        # exactly equal is still one packet, docs/wire.md), and the partial packet is dropped
        # (counted as truncated) the moment the clock passes it, before the second half comes.
        control_path = os.path.join(self.dir.name, "control.sock")
        self.start("--timing", "manual", "--control", control_path,
                   "--servo", "xm430-w350:3", "--servo", "ax-12a:5")
        control = Control(control_path)
        self.addCleanup(control.close)
        port = Port(self.link)
        self.addCleanup(port.close)
        sent = 0

        def send_split(packet, cut, gap_ns):
            """Writes packet[:cut], steps the clock by gap_ns once the daemon has read it, then
            writes the rest; returns the counters before, after the step and at the end."""
            nonlocal sent
            before = control.call("stats", port="dxl0")["dxl0"]
            port.write(packet[:cut])
            sent += cut
            heard(control, sent)  # stamped before the clock moves
            if gap_ns:
                control.call("clock.step", ns=gap_ns)
            stepped = control.call("stats", port="dxl0")["dxl0"]
            port.write(packet[cut:])
            sent += len(packet) - cut
            return before, stepped, heard(control, sent)

        def assert_answered(counters, reply):
            before, stepped, after = counters
            self.assertEqual(stepped["truncated"], before["truncated"])
            self.assertEqual((after["frames"], after["truncated"]),
                             (before["frames"] + 1, before["truncated"]))
            self.assertEqual(reply, reply_expected)

        def assert_dropped(counters, reply):
            before, stepped, after = counters
            self.assertEqual(stepped["truncated"], before["truncated"] + 1)  # at the timeout
            self.assertEqual((after["frames"], after["replies"]),
                             (before["frames"], before["replies"]))
            self.assertIsNone(reply)

        for protocol, packet, cut, timeout_ns in ((2, packet2(3, PING), 4, 1_500_000),
                                                  (1, packet1(5, PING), 3, 100_000_000)):
            if protocol == 1:
                port.set_baud(1000000)  # the AX-12A's factory rate
            receive = port.status2 if protocol == 2 else port.status1
            reply_expected = (3, 0, XM430_W350_PING) if protocol == 2 else (5, 0, b"")
            for gap_ns in (0, timeout_ns - 1, timeout_ns):
                with self.subTest(protocol=protocol, gap_ns=gap_ns):
                    assert_answered(send_split(packet, cut, gap_ns), receive())
            with self.subTest(protocol=protocol, gap_ns=timeout_ns + 1):
                assert_dropped(send_split(packet, cut, timeout_ns + 1), receive(timeout=0.05))
            port.write(packet)  # the line is clean again: the whole packet is answered
            sent += len(packet)
            self.assertEqual(receive(), reply_expected)

    def test_in_realtime_a_protocol_1_packet_split_across_writes_is_timed_by_the_wall_clock(self):
        # Realtime timing stamps the bytes with the wall clock: 20 ms apart is within 1.0's
        # 100 ms inter-byte timeout, 300 ms apart (a sleep is never shorter) is past it.
        self.start("--servo", "ax-12a:5")
        port = Port(self.link, 1000000)
        self.addCleanup(port.close)
        ping = packet1(5, PING)
        port.write(ping[:3])
        time.sleep(0.02)
        port.write(ping[3:])
        self.assertEqual(port.status1(), (5, 0, b""))
        port.write(ping[:3])
        time.sleep(0.3)
        port.write(ping[3:])
        self.assertIsNone(port.status1(timeout=0.3))

    def test_a_client_at_another_baud_rate_gets_no_answer(self):
        _, control = self.start_manual()
        port = Port(self.link, 115200)
        assert_unanswered(control, port, packet2(1, PING))
        port.set_baud(57600)
        port.write(packet2(1, PING))
        self.assertEqual(port.status2(), (1, 0, XM430_W350_PING))
        port.close()

    def test_reply_time_is_at_least_the_modelled_time(self):
        self.start()
        port = Port(self.link)
        start = time.monotonic()
        port.write(packet2(1, PING))
        self.assertIsNotNone(port.status2())
        elapsed = time.monotonic() - start
        # 10 + 14 bytes at 57600 baud, 50 us processing, 500 us Return Delay Time: 4.72 ms.
        self.assertGreaterEqual(elapsed, 0.0045)
        self.assertLess(elapsed, 0.5)
        port.close()

    def test_baud_option_moves_every_servo_to_that_rate(self):
        self.start_manual("--baud", "1000000")
        port = Port(self.link, 1000000)
        port.write(packet2(2, PING))
        self.assertEqual(port.status2(), (2, 0, XM430_W350_PING))
        port.write(packet2(2, READ, bytes([8, 0, 1, 0])))  # Baud Rate item: index 3 is 1 Mbps
        self.assertEqual(port.status2(), (2, 0, b"\x03"))
        port.close()

    def test_protocol_option_switches_x_servos_to_protocol_1(self):
        _, control = self.start_manual("--protocol", "1")
        port = Port(self.link)
        port.write(packet1(1, PING))
        self.assertEqual(port.status1(), (1, 0, b""))
        assert_unanswered(control, port, packet2(1, PING))
        port.close()

    def test_sigterm_stops_cleanly_and_removes_the_link(self):
        daemon = Daemon("--link", self.link)
        self.assertTrue(os.path.islink(self.link))
        self.assertEqual(daemon.stop(), 0)
        self.assertFalse(os.path.lexists(self.link))

    def test_bad_servo_options_are_refused_with_exit_code_2(self):
        for args, message in [(["--servo", "xm999:1"], 'unknown model "xm999"'),
                              (["--servo", "xm430-w350:x"], "the ID part must be a number"),
                              (["--servo", "xm430-w350:5-2"], "IDs must lie in 0 ~ 252"),
                              (["--servo", "ax-12a:1", "--baud", "4500000"],
                               "--baud: ax-12a cannot do 4500000 bps (it offers 1000000"),
                              (["--servo", "xl-320:1", "--protocol", "1"],
                               "--protocol: xl-320 cannot speak Protocol 1.0; the models that "
                               "can: "),
                              (["--servo", "xm430-w350:1", "--protocol", "modbus"],
                               "--protocol: xm430-w350 cannot speak Modbus RTU; the models that "
                               "can: ph42-020-s300-r"),
                              (["--servo", "ph42-020-s300-r:0", "--protocol", "modbus"],
                               "servo ph42-020-s300-r:0 speaks Modbus RTU, whose IDs are 1 ~ 247"),
                              (["--timing", "slow"], "--timing: slow not in"),
                              (["--config", "x.json", "--servo", "ax-12a:1"],
                               "--config excludes --servo")]:
            result = subprocess.run(dxlemu_command("run", "--link", self.link, *args),
                                    capture_output=True, text=True, timeout=10)
            self.assertEqual(result.returncode, 2, args)
            self.assertIn(message, result.stderr)
            self.assertFalse(os.path.lexists(self.link))


    def write_config(self, config):
        path = os.path.join(self.dir.name, "bus.json")
        with open(path, "w") as f:
            json.dump(config, f)
        return path

    def test_a_config_serves_several_ports_with_their_overrides(self):
        arm = os.path.join(self.dir.name, "arm")
        legs = os.path.join(self.dir.name, "legs")
        config = self.write_config({"ports": [
            {"name": "arm", "link": arm, "servos": [
                {"model": "xm430-w350", "ids": [1, 2], "items": {"return_delay_time": 0}}]},
            {"name": "legs", "link": legs, "servos": [
                {"model": "ax-12a", "id": 7, "baud": 57600}]}]})
        daemon = Daemon("--config", config, "--timing", "manual")
        self.addCleanup(daemon.stop)
        self.assertEqual(daemon.ready["port"], "arm")
        second = json.loads(daemon.proc.stdout.readline())
        self.assertEqual(second, {"event": "ready", "port": "legs", "pty": second["pty"],
                                  "link": legs, "servos": [{"id": 7, "model": "ax-12a"}],
                                  "control": daemon.ready["control"], "seed": 1})
        port = Port(arm)
        port.write(packet2(2, READ, bytes([9, 0, 1, 0])))  # Return Delay Time
        self.assertEqual(port.status2(), (2, 0, b"\x00"))
        port.close()
        port = Port(legs)
        port.write(packet1(7, READ, bytes([4, 1])))  # Baud Rate: 34 is 57600 bps
        self.assertEqual(port.status1(), (7, 0, b"\x22"))
        port.write(packet1(7, WRITE, bytes([25, 1])))  # LED on
        self.assertEqual(port.status1(), (7, 0, b""))
        port.write(packet1(7, READ, bytes([25, 1])))
        self.assertEqual(port.status1(), (7, 0, b"\x01"))
        port.close()
        self.assertEqual(daemon.stop(), 0)
        self.assertFalse(os.path.lexists(arm) or os.path.lexists(legs))

    def test_check_validates_a_config_and_a_bad_one_is_refused_with_exit_code_2(self):
        good = self.write_config({"ports": [{"name": "dxl0", "servos": [
            {"model": "xm430-w350", "id": 1}]}]})
        result = subprocess.run(dxlemu_command("check", good), capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn(good + ": ok", result.stdout)
        bad = self.write_config({"ports": [{"name": "dxl0", "link": self.link, "servos": [
            {"model": "xm430-w350", "id": 1, "items": {"return_delay_time": 999}}]}]})
        expected = (bad + ": /ports/0/servos/0/items/return_delay_time: xm430-w350 "
                    "return_delay_time 999 is outside its range 0 ~ 254")
        for command in (["check", bad], ["run", "--config", bad]):
            result = subprocess.run(dxlemu_command(*command), capture_output=True, text=True,
                                    timeout=10)
            self.assertEqual(result.returncode, 2, command)
            self.assertEqual(result.stderr.strip(), "dxlemu: " + expected)
            self.assertEqual(result.stdout, "")  # no readiness line: nothing started
            self.assertFalse(os.path.lexists(self.link))

    def test_state_keeps_eeprom_across_restarts_and_is_saved_at_once(self):
        state = os.path.join(self.dir.name, "state.json")
        daemon = self.start("--state", state, "--timing", "manual")
        port = Port(self.link)
        port.write(packet2(2, WRITE, bytes([9, 0, 10])))  # Return Delay Time 10
        self.assertEqual(port.status2(), (2, 0, b""))
        port.write(packet2(3, WRITE, bytes([7, 0, 30])))  # ID 3 becomes 30
        self.assertEqual(port.status2(), (3, 0, b""))
        port.write(packet2(1, WRITE, bytes([64, 0, 1])))  # Torque Enable (RAM): not kept
        self.assertEqual(port.status2(), (1, 0, b""))
        port.close()
        # Saved before each Write's status was sent (docs/config.md): in the file by the time
        # the client has read the status, so even kill -9 right after keeps it.
        with open(state) as f:
            servos = json.load(f)["ports"]["dxl0"]
        self.assertEqual(servos[1]["eeprom"]["return_delay_time"], 10)
        self.assertEqual(servos[2]["eeprom"]["id"], 30)
        daemon.proc.send_signal(signal.SIGKILL)
        daemon.proc.wait()
        os.unlink(self.link)  # a killed daemon cannot remove its link
        ready = self.start("--state", state, "--timing", "manual").ready
        self.assertEqual([s["id"] for s in ready["servos"]], [1, 2, 30])
        port = Port(self.link)
        port.write(packet2(0xFE, PING))
        self.assertEqual([port.status2()[0] for _ in range(3)], [1, 2, 30])
        port.write(packet2(2, READ, bytes([9, 0, 1, 0])))
        self.assertEqual(port.status2(), (2, 0, b"\x0a"))
        port.write(packet2(1, READ, bytes([64, 0, 1, 0])))
        self.assertEqual(port.status2(), (1, 0, b"\x00"))
        port.close()

    def test_a_broken_state_file_is_refused_with_exit_code_2(self):
        state = os.path.join(self.dir.name, "state.json")
        with open(state, "w") as f:
            f.write('{"format": "dxlemu-state", "version": 1, "ports": '
                    '{"dxl0": [{"model": "xm430-w350", "eeprom": {"id": 300}}]}}')
        result = subprocess.run(dxlemu_command("run", "--link", self.link, "--state", state),
                                capture_output=True, text=True, timeout=10)
        self.assertEqual(result.returncode, 2)
        self.assertIn(state + ": /ports/dxl0/0/eeprom/id: 300 is outside", result.stderr)
        self.assertFalse(os.path.lexists(self.link))

    def read_trace(self, path):
        with open(path) as f:
            return [json.loads(line) for line in f]

    def test_trace_writes_every_packet_both_ways_decoded(self):
        # Realtime timing, the one that models reply delays, which the trace's times show; a
        # reply the loaded machine made late is traced at its modelled time all the same, and
        # sent rather than dropped.
        trace = os.path.join(self.dir.name, "trace.jsonl")
        daemon = self.start("--trace", trace, "--late-reply-limit-ms", "0")
        port = Port(self.link)
        port.write(packet2(1, READ, bytes([132, 0, 4, 0])))
        self.assertIsNotNone(port.status2())
        port.write(packet2(1, PING)[:-1] + b"\x00")  # bad CRC: answered with CRC Error
        self.assertEqual(port.status2()[1], 0x03)
        port.close()
        self.assertEqual(daemon.stop(), 0)
        lines = self.read_trace(trace)
        self.assertEqual([(line["dir"], line.get("packet", line.get("problem")))
                          for line in lines],
                         [("in", "id=1 read address=132 length=4"),
                          ("out", "id=1 error=0x00 params=00 08 00 00"),  # 2048
                          ("in", "bad_check"),
                          ("out", "id=1 error=0x03")])
        # Modelled time: the reply's last byte arrives after the instruction's plus the delays.
        self.assertGreater(lines[1]["t"] - lines[0]["t"], 0.0005 + 0.00005)

    def test_fast_timing_replies_at_once_and_manual_timing_keeps_time_still(self):
        for mode, others in (("fast", ["--late-reply-limit-ms", "0"]), ("manual", [])):
            trace = os.path.join(self.dir.name, mode + ".jsonl")
            daemon = Daemon("--link", self.link, "--timing", mode, "--trace", trace, *others)
            port = Port(self.link)
            time.sleep(0.01)
            port.write(packet2(0xFE, PING))
            self.assertEqual([port.status2()[0] for _ in range(3)], [1, 2, 3])
            port.close()
            self.assertEqual(daemon.stop(), 0)
            times = {line["t"] for line in self.read_trace(trace)}
            self.assertEqual(len(times), 1, mode)  # every reply at the instruction's time
            if mode == "manual":
                self.assertEqual(times, {0.0})  # the 10 ms slept did not move the clock
            else:
                self.assertGreaterEqual(min(times), 0.01)  # fast follows the wall clock

    def test_log_level_error_keeps_stderr_quiet_and_debug_tells_more(self):
        state = os.path.join(self.dir.name, "state.json")
        for level, expected in (("error", []),
                                ("debug", ["info: dxl0: 3 servos on /dev/pts/",
                                           "debug: saved the EEPROM of every servo to " + state,
                                           "info: stopping on SIGTERM"])):
            daemon = Daemon("--link", self.link, "--log-level", level, "--state", state)
            daemon.proc.send_signal(signal.SIGTERM)
            stderr = daemon.proc.stderr.read()
            self.assertEqual(daemon.stop(), 0)
            if not expected:
                self.assertEqual(stderr, "")
            for text in expected:
                self.assertIn(text, stderr)


class ModelLibraryTest(unittest.TestCase):
    """A start reads the model catalogs and parses only the model files it needs
    (docs/model-format.md "The catalog"): over a copy of the shipped library in which every model
    file but XM430-W350's is broken, a bus of XM430-W350 starts and serves, and a bus or config
    naming a broken model is refused with exit status 2 and the file's refusal."""

    SHIPPED = Path(__file__).resolve().parents[2] / "models"

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.models = Path(self.dir.name) / "models"
        shutil.copytree(self.SHIPPED, self.models)
        for path in self.models.rglob("*.json"):
            if path.name != "catalog.json" and path.parent.name != "schema" and path.stem != "xm430-w350":
                path.write_text('{ "name": ')
        # A file that parses but says another model number than its catalog entry.
        xm430_w210 = json.loads((self.SHIPPED / "xm430-w210.json").read_text())
        xm430_w210["model_number"] = 1
        (self.models / "xm430-w210.json").write_text(json.dumps(xm430_w210))
        patch = mock.patch.dict(os.environ, {"DXLEMU_MODELS_DIR": str(self.models)})
        patch.start()
        self.addCleanup(patch.stop)
        self.link = os.path.join(self.dir.name, "dxl0")

    def test_a_bus_of_one_model_starts_without_reading_the_others(self):
        daemon = Daemon("--link", self.link, "--servo", "xm430-w350:1-3")
        self.addCleanup(daemon.stop)
        self.assertEqual(daemon.ready["servos"], [{"id": i, "model": "xm430-w350"} for i in (1, 2, 3)])
        port = Port(self.link)
        port.write(packet2(3, PING))
        self.assertEqual(port.status2(), (3, 0, XM430_W350_PING))
        port.close()
        self.assertEqual(daemon.stop(), 0)

    def test_run_and_check_refuse_a_broken_model_file_with_exit_code_2(self):
        config = os.path.join(self.dir.name, "bus.json")
        with open(config, "w") as f:
            json.dump({"ports": [{"name": "dxl0", "link": self.link, "servos": [
                {"model": "xm430-w350", "id": 1}, {"model": "ax-12a", "id": 2}]}]}, f)
        broken = str(self.models / "ax-12a.json") + ": /: not valid JSON: "
        disagrees = (str(self.models / "xm430-w210.json") + ": /model_number: is 1, but its entry in "
                     + str(self.models / "catalog.json") + " (/models/")
        for command, message in [(["run", "--link", self.link, "--servo", "ax-12a:1"], broken),
                                 (["run", "--config", config], broken),
                                 (["check", config], broken),
                                 (["run", "--link", self.link, "--servo", "xl330-m288@52:1"],
                                  str(self.models / "xl330-m288.json") + ": /: not valid JSON: "),
                                 (["run", "--link", self.link, "--servo", "xm430-w210:1"], disagrees)]:
            result = subprocess.run(dxlemu_command(*command), capture_output=True, text=True,
                                    timeout=30)
            self.assertEqual(result.returncode, 2, (command, result.stderr))
            self.assertTrue(result.stderr.startswith("dxlemu: " + message), (command, result.stderr))
            self.assertEqual(result.stdout, "")  # no readiness line: nothing started
            self.assertFalse(os.path.lexists(self.link))

    def test_models_lists_the_library_and_refuses_a_broken_file(self):
        result = subprocess.run(dxlemu_command("models", "--name", "xm430-w350"),
                                capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertRegex(result.stdout, r"xm430-w350 +1020 +2.0,1.0 +x")
        result = subprocess.run(dxlemu_command("models"), capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 2)
        self.assertRegex(result.stderr, r"^dxlemu: .*\.json: /: not valid JSON: ")


if __name__ == "__main__":
    unittest.main()
