"""End-to-end tests of `dxlemu exec` and its preload library (docs/exec.md): real clients
(exec_client.py) on the real daemon's PTY, with and without exec."""
import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from unittest import mock

from dxl_client import Control, Daemon, dxlemu_command, packet2, timeout_scale

CLIENT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "exec_client.py")
# What the master's line discipline holds for a reader that does not read: an output flush on
# the client's side discards only what is beyond it (exec_client.py's flushed_bytes).
LINE_DISCIPLINE_BYTES = 4096
SYNC_WRITE_BYTES = len(packet2(0xFE, 0x83, bytes(10)))  # exec_client.py's LED Sync Write
# Packets per flood: twice what the line discipline holds, so that a flush has packets to find.
FLOOD = 2 * LINE_DISCIPLINE_BYTES // SYNC_WRITE_BYTES


def run(args, env=None, timeout=60):
    """(exit status, stdout, stderr) of `args`, with `env` added to this environment."""
    environment = dict(os.environ)
    environment.update(env or {})
    result = subprocess.run(args, capture_output=True, text=True, env=environment,
                            timeout=timeout * timeout_scale())
    return result.returncode, result.stdout, result.stderr


def client(*args):
    return [sys.executable, CLIENT, *args]


class ExecTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.runtime = os.path.join(self.dir.name, "runtime")
        os.mkdir(self.runtime)
        self.link = os.path.join(self.dir.name, "dxl0")
        # The daemon's default control socket goes to the test's own XDG_RUNTIME_DIR.
        with mock.patch.dict(os.environ, {"XDG_RUNTIME_DIR": self.runtime}):
            # Manual timing: the Ping's reply goes out at once, however late the daemon runs.
            self.daemon = Daemon("--link", self.link, "--timing", "manual")
        self.addCleanup(self.daemon.stop)
        self.control = Control(self.daemon.ready["control"])
        self.addCleanup(self.control.close)

    def exec(self, *args, env=None):
        """`dxlemu exec ARGS` with the test's XDG_RUNTIME_DIR."""
        return run(dxlemu_command("exec", *args), env={"XDG_RUNTIME_DIR": self.runtime, **(env or {})})

    def result(self, code, out, err):
        self.assertEqual(code, 0, err)
        return json.loads(out)

    def frames(self):
        return self.control.call("stats", port="dxl0")["dxl0"]["frames"]

    def flood_heard(self, *prefix, mode="tcflush"):
        """How many of FLOOD flushed Sync Writes the daemon decoded (its Ping aside). The daemon
        is stopped (SIGSTOP) while the client writes, so that packets wait in the PTY for the
        next flush, as they do whenever a client writes faster than the daemon reads (the loss
        is otherwise a race with the kernel's PTY worker, which a slow daemon may never lose);
        it goes on once the client has written everything, Ping included."""
        before = self.frames()
        pid = self.daemon.proc.pid
        os.kill(pid, signal.SIGSTOP)
        try:
            flood = subprocess.Popen([*prefix, *client("flood", self.link, str(FLOOD), mode)],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            self.addCleanup(flood.kill)  # a client left waiting by a failed check
            ready, _, _ = select.select([flood.stdout], [], [], 30 * timeout_scale())
            written = json.loads(flood.stdout.readline()) if ready else None
        finally:
            os.kill(pid, signal.SIGCONT)
        self.assertEqual(written, {"written": FLOOD * SYNC_WRITE_BYTES + len(packet2(1, 0x01))},
                         "the client did not write everything")
        out, err = flood.communicate(timeout=60 * timeout_scale())
        self.assertTrue(self.result(flood.returncode, out, err)["ping_answered"])
        return self.frames() - before - 1

    def test_an_output_flush_before_each_packet_loses_nothing_under_exec(self):
        exec_prefix = dxlemu_command("exec", "--port", self.link, "--")
        for mode in ("tcflush", "ioctl"):
            with self.subTest(mode=mode):
                self.assertEqual(self.flood_heard(*exec_prefix, mode=mode), FLOOD)

    def test_an_output_flush_before_each_packet_loses_packets_on_a_bare_pty(self):
        # What the line discipline held when the flushes came, and the last packet, written
        # after the last flush: every other packet was discarded.
        for mode in ("tcflush", "ioctl"):
            with self.subTest(mode=mode):
                self.assertLessEqual(self.flood_heard(mode=mode),
                                     LINE_DISCIPLINE_BYTES // SYNC_WRITE_BYTES + 1)

    def test_the_sdk_open_with_low_latency_modem_lines_and_rs485_work_under_exec_only(self):
        bare = self.result(*run(client("serial", self.link)))
        self.assertEqual(bare, {"low_latency": {"errno": "ENOTTY"}, "modem": {"errno": "ENOTTY"},
                                "rs485": {"errno": "ENOTTY"}})
        out = self.result(*self.exec("--port", self.link, "--", *client("serial", self.link)))
        # type PORT_UNKNOWN, line, port, irq 0, no flags, no FIFO size, no divisor, 60 MHz
        self.assertEqual(out["low_latency"], {"ok": {"before": [0, 0, 0, 0, 0, 0, 0, 60000000],
                                                     "flags_after": 1 << 13}})
        tiocm_dtr, tiocm_rts = 0x002, 0x004
        # At open DTR and RTS are raised; RTS cleared, set again, then both cleared.
        self.assertEqual(out["modem"], {"ok": [tiocm_dtr | tiocm_rts, tiocm_dtr,
                                               tiocm_dtr | tiocm_rts, 0]})
        self.assertEqual(out["rs485"], {"ok": {"flags_before": 0, "flags_after": 3}})
        # Through the PTY's own path (the link's target) as well: one device, one state.
        pty = self.daemon.ready["pty"]
        self.assertEqual(self.result(*self.exec("--", *client("serial", pty)))["modem"]["ok"][0],
                         tiocm_dtr | tiocm_rts)

    def test_a_pty_that_is_not_dxlemus_is_left_alone_under_exec(self):
        out = self.result(*self.exec("--port", self.link, "--", *client("foreign")))
        for request in ("low_latency", "modem", "rs485"):
            self.assertEqual(out[request], {"errno": "ENOTTY"}, request)
        # Unflushed, everything written arrives; flushed, more than the 4 KiB the kernel had
        # already moved on is discarded.
        self.assertGreater(out["none"]["written"], 4096)
        self.assertEqual(out["none"]["read"], out["none"]["written"])
        for mode in ("tcflush", "ioctl"):
            self.assertGreater(out[mode]["written"], 4096, mode)
            self.assertLessEqual(out[mode]["read"], 4096, mode)

    def test_the_ports_come_from_port_options_a_control_socket_or_every_running_daemon(self):
        show = [sys.executable, "-c",
                "import os; print(os.environ['DXLEMU_PTYS']); print(os.environ['LD_PRELOAD'])"]
        pty = self.daemon.ready["pty"]
        code, out, err = self.exec("--", *show, env={"LD_PRELOAD": "", "DXLEMU_PTYS": ""})
        self.assertEqual(code, 0, err)
        ptys, preload = out.splitlines()
        self.assertEqual(ptys, f"{pty}:{self.link}")
        self.assertTrue(preload.endswith("/libdxlemu-preload.so"), preload)
        self.assertTrue(os.path.isfile(preload), preload)
        code, out, err = self.exec("--control", self.daemon.ready["control"], "--", *show,
                                   env={"DXLEMU_PTYS": "/dev/ttyUSB9"})
        self.assertEqual((code, out.splitlines()[0]), (0, f"/dev/ttyUSB9:{pty}:{self.link}"), err)
        # Without --, from the first argument that is not exec's; an existing LD_PRELOAD kept.
        code, out, err = self.exec("--port", self.link, *show, env={"LD_PRELOAD": "/lib/x.so"})
        self.assertEqual(code, 0, err)
        self.assertEqual(out.splitlines()[0], self.link)
        self.assertEqual(out.splitlines()[1], f"/lib/x.so:{preload}")

    def test_the_exit_status_is_the_commands_or_128_plus_the_signal_that_killed_it(self):
        self.assertEqual(self.exec("--", "sh", "-c", "exit 7")[0], 7)
        self.assertEqual(self.exec("--", "sh", "-c", "kill -KILL $$")[0], 128 + signal.SIGKILL)
        code, _, err = self.exec("--", "no-such-command-here")
        self.assertEqual(code, 127)
        self.assertIn("dxlemu exec: cannot run no-such-command-here: No such file", err)
        # A SIGTERM sent to dxlemu exec reaches the command.
        started = os.path.join(self.dir.name, "started")
        proc = subprocess.Popen(
            dxlemu_command("exec", "--port", self.link, "--", "sh", "-c",
                           f"touch {started}; exec sleep 60"), stderr=subprocess.PIPE)
        deadline = time.monotonic() + 10 * timeout_scale()
        while not os.path.exists(started) and time.monotonic() < deadline:
            time.sleep(0.01)
        proc.send_signal(signal.SIGTERM)
        self.assertEqual(proc.wait(timeout=10 * timeout_scale()), 128 + signal.SIGTERM)
        proc.stderr.close()

    def test_no_pty_found_or_no_preload_library_is_a_clear_error_and_runs_nothing(self):
        marker = os.path.join(self.dir.name, "ran")
        touch = ["sh", "-c", f"touch {marker}"]
        empty = os.path.join(self.dir.name, "empty")
        os.mkdir(empty)
        code, _, err = run(dxlemu_command("exec", "--", *touch), env={"XDG_RUNTIME_DIR": empty})
        self.assertEqual(code, 125)
        self.assertIn(f"dxlemu exec: no dxlemu PTY to protect: no running dxlemu found (no live "
                      f"control socket {empty}/dxlemu-*.sock); pass --port PATH or --control "
                      "SOCKET", err)
        code, _, err = self.exec("--port", os.path.join(self.dir.name, "nope"), "--", *touch)
        self.assertEqual(code, 125)
        self.assertIn("nope: not a character device (a dxlemu PTY or its link)", err)
        code, _, err = self.exec("--port", self.link, "--", *touch,
                                 env={"DXLEMU_PRELOAD": "/nonexistent/lib.so"})
        self.assertEqual(code, 125)
        self.assertIn("DXLEMU_PRELOAD names /nonexistent/lib.so, which does not exist", err)
        code, _, err = self.exec("--port", self.link)
        self.assertEqual(code, 125)
        self.assertIn("no COMMAND to run", err)
        self.assertFalse(os.path.exists(marker))


if __name__ == "__main__":
    unittest.main()
