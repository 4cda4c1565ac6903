"""Starting and stopping the dxlemu daemon (`dxlemu run`) from Python.

`DaemonProcess` runs `dxlemu run ARGS` as given and reads its readiness lines (one JSON object
per port on stdout, printed once every port is open). `Emulator` builds those arguments for a
bus in a temporary directory of its own (PTY link, control socket) and connects a control
client: the usual way to get an emulator for a test or a script.

Three environment variables serve the memory checks (scripts/test.sh's ASan + UBSan run,
scripts/memcheck.sh): $DXLEMU_WRAPPER, a command the daemon is run under, split as a shell
would (`valgrind --error-exitcode=99 --log-file=...`); $DXLEMU_TIMEOUT_SCALE, what the start
and stop timeouts are multiplied by for a daemon slowed down that way; and $DXLEMU_CHECK_EXIT=1,
with which `DaemonProcess.stop` raises DaemonError unless the daemon exited with status 0, so
that a sanitizer's or valgrind's report at exit (which changes the exit status) fails the test
that started the daemon even when everything it checked passed.
"""
from __future__ import annotations

import json
import os
import select
import shlex
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from typing import IO, NamedTuple, Sequence

from ._places import checkout_binaries, installed_binary
from .control import Control, ControlError
from .protocol import Client


class DaemonError(Exception):
    """The daemon could not be found or run (the message names the path), exited before it
    was ready, or did not get ready in time. `stderr` holds what it wrote there, `returncode`
    its exit status (None if it is running or never ran)."""

    def __init__(self, message: str, stderr: str = "", returncode: int | None = None):
        super().__init__(f"{message}\n{stderr.rstrip()}" if stderr.strip() else message)
        self.stderr = stderr
        self.returncode = returncode


def find_binary(binary: str | os.PathLike | None = None) -> str:
    """The dxlemu executable: `binary` when given, else $DXLEMU_BIN, else `dxlemu` on PATH, else
    the one installed with this package (`cmake --install`, the .deb: `bin/dxlemu` of its
    prefix), else the build of the checkout this package sits in or was pip-installed from
    (build/emulator/dxlemu)."""
    if binary is not None:
        return os.fspath(binary)
    if os.environ.get("DXLEMU_BIN"):
        return os.environ["DXLEMU_BIN"]
    on_path = shutil.which("dxlemu")
    if on_path:
        return on_path
    installed = installed_binary()
    places = ([installed] if installed is not None else []) + checkout_binaries()
    for place in places:
        if place.is_file():
            return str(place)
    raise DaemonError("no dxlemu binary: pass one, set DXLEMU_BIN, put dxlemu on PATH, or build "
                      f"the checkout (looked for {', '.join(map(str, places))})")


def wrapper_command() -> list[str]:
    """$DXLEMU_WRAPPER split as a shell would: the command the daemon runs under (empty when
    unset)."""
    return shlex.split(os.environ.get("DXLEMU_WRAPPER", ""))


def timeout_scale() -> float:
    """$DXLEMU_TIMEOUT_SCALE (1 when unset): the factor of the daemon's start and stop
    timeouts."""
    return float(os.environ.get("DXLEMU_TIMEOUT_SCALE") or 1)


def _checks_exit() -> bool:
    """$DXLEMU_CHECK_EXIT=1: a daemon that did not exit with status 0 fails its `stop`."""
    return os.environ.get("DXLEMU_CHECK_EXIT", "") not in ("", "0")


class _Drain(threading.Thread):
    """Reads a pipe to its end in the background, so the daemon never blocks writing to it."""

    def __init__(self, pipe: IO[str]):
        super().__init__(daemon=True)
        self._pipe = pipe
        self._parts: list[str] = []
        self._lock = threading.Lock()
        self.start()

    def run(self) -> None:
        for line in self._pipe:
            with self._lock:
                self._parts.append(line)

    def text(self) -> str:
        """Everything read so far."""
        with self._lock:
            return "".join(self._parts)


class DaemonProcess:
    """`dxlemu run ARGS` as a child process, ready once it printed `ports` readiness lines.

    `proc` is the subprocess.Popen (stdout and stderr are text pipes); `ready` the readiness
    lines as dicts. With `drain_stderr` (the default) stderr is collected in the background
    (`stderr()`); without it the caller reads `proc.stderr` itself, and closes it. Raises
    DaemonError when the binary cannot be run (naming it), and, with the daemon's stderr, when
    it exits or stays silent for `timeout` seconds before it is ready. `args` is the whole
    command: $DXLEMU_WRAPPER's words, if any, then the binary, `run` and ARGS."""

    def __init__(self, args: Sequence[str], *, binary: str | os.PathLike | None = None,
                 ports: int = 1, timeout: float = 10.0, drain_stderr: bool = True):
        self.binary = find_binary(binary)
        self.args = [*wrapper_command(), self.binary, "run", *map(str, args)]
        self._killed = False  # by `stop`, after the daemon ignored SIGTERM
        self._checked = not _checks_exit()
        try:
            self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                                         text=True)
        except OSError as error:  # missing, not executable, not a program: the path it tried
            raise DaemonError(f"cannot run {error.filename or self.args[0]}: "
                              f"{error.strerror or error} ({' '.join(self.args)})") from error
        self._drain = _Drain(self.proc.stderr) if drain_stderr else None
        try:
            deadline = time.monotonic() + timeout * timeout_scale()
            self.ready: list[dict] = [self._readiness_line(deadline) for _ in range(ports)]
        except BaseException:
            self._stop(timeout=2.0)
            raise

    def _readiness_line(self, deadline: float) -> dict:
        """One line of stdout, read byte by byte from the pipe so that nothing after it is
        taken from `proc.stdout` (callers may read further lines themselves)."""
        fd = self.proc.stdout.fileno()
        line = bytearray()
        while not line.endswith(b"\n"):
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                raise self._failure(f"{self.binary} not ready in time (no readiness line)")
            byte = os.read(fd, 1)
            if not byte:
                raise self._failure(f"{self.binary} exited before it was ready")
            line += byte
        try:
            ready = json.loads(line)
        except ValueError:
            raise self._failure(f"not a readiness line: {line.decode(errors='replace')!r}")
        if not isinstance(ready, dict) or ready.get("event") != "ready":
            raise self._failure(f"not a readiness line: {ready!r}")
        return ready

    def _failure(self, message: str) -> DaemonError:
        """A DaemonError with the exit status and stderr, after stopping the process."""
        code = self._stop(timeout=2.0)
        return DaemonError(f"{message} ({' '.join(self.args)}; exit status {code})",
                           self.stderr(), code)

    def stderr(self) -> str:
        """What the daemon wrote to stderr so far (all of it once stopped); empty when the
        caller reads the pipe itself."""
        if self._drain is not None:
            return self._drain.text()
        if self.proc.stderr.closed or self.proc.poll() is None:
            return ""
        text = self.proc.stderr.read()
        self.proc.stderr.close()
        return text

    @property
    def running(self) -> bool:
        """True while the process has not exited."""
        return self.proc.poll() is None

    def wait(self, timeout: float | None = None) -> int:
        """Waits for the process to exit; its exit status (subprocess.TimeoutExpired if not)."""
        return self.proc.wait(timeout=timeout)

    def stop(self, timeout: float = 5.0) -> int:
        """SIGTERM (the daemon stops cleanly), then SIGKILL if it has not exited within
        `timeout` seconds; returns the exit status. Safe to call more than once. With
        $DXLEMU_CHECK_EXIT=1 the first call raises DaemonError, with the daemon's stderr,
        unless the status is 0 (or the daemon was killed with SIGKILL before this call)."""
        code = self._stop(timeout)
        if not self._checked:
            self._checked = True
            if self._killed:
                problem = f"did not exit within {timeout * timeout_scale():g} s of SIGTERM"
            elif code > 0:
                problem = f"exited with status {code}"
            elif code < 0 and code != -signal.SIGKILL:
                problem = f"died of signal {-code} ({signal.strsignal(-code)})"
            else:
                problem = ""
            if problem:
                raise DaemonError(f"{self.binary} {problem} ({' '.join(self.args)})",
                                  self.stderr(), code)
        return code

    def _stop(self, timeout: float) -> int:
        """`stop` without the exit status check."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=timeout * timeout_scale())
            except subprocess.TimeoutExpired:
                self._killed = True
                self.proc.kill()
                self.proc.wait()
        self.proc.stdout.close()
        if self._drain is not None:
            self._drain.join(timeout=timeout)
            self.proc.stderr.close()
        return self.proc.returncode


class PortInfo(NamedTuple):
    """One port of the running bus, from its readiness line."""

    name: str
    pty: str
    link: str
    servos: list[dict]


def _config_port_count(config: str | os.PathLike) -> int:
    """How many ports a config file declares (1 when it cannot be read: the daemon will say
    what is wrong with it)."""
    try:
        with open(config, encoding="utf-8") as f:
            return max(1, len(json.load(f)["ports"]))
    except (OSError, ValueError, KeyError, TypeError):
        return 1


class Emulator:
    """A running dxlemu with its own temporary directory for the PTY link (`dxl0`) and the
    control socket, and a connected `control` client. Usable as a context manager.

    Every argument maps to a `dxlemu run` option (README.md "Running the emulator"): `servos`
    (["xm430-w350:1-3"], the daemon's default when None), `config` (a bus config file, instead
    of `servos` and `link`), `timing` ("realtime", "fast", "manual"), `seed` (fault injection's
    random numbers), `baud`, `protocol`, `tick_hz`, `state`, `trace`, `log_level`, `models`
    (extra model directories); `link` overrides where port dxl0's link goes; `args` are added
    as given. `binary` as in `find_binary`. Raises DaemonError when the daemon does not start."""

    def __init__(self, *, servos: Sequence[str] | None = None,
                 config: str | os.PathLike | None = None, timing: str | None = None,
                 seed: int | None = None, baud: int | None = None, protocol: int | None = None,
                 tick_hz: int | None = None, state: str | os.PathLike | None = None,
                 trace: str | os.PathLike | None = None, log_level: str | None = None,
                 models: Sequence[str | os.PathLike] = (), link: str | os.PathLike | None = None,
                 args: Sequence[str] = (), binary: str | os.PathLike | None = None,
                 timeout: float = 10.0):
        self._dir = tempfile.TemporaryDirectory(prefix="dxlemu-")
        self.directory = self._dir.name
        """The temporary directory (removed by `stop`)."""
        self.control_path = os.path.join(self.directory, "control.sock")
        argv: list[str] = ["--control", self.control_path]
        if config is not None:
            argv += ["--config", os.fspath(config)]
        else:
            argv += ["--link", os.fspath(link) if link else os.path.join(self.directory, "dxl0")]
            for servo in servos or ():
                argv += ["--servo", servo]
        options = {"--timing": timing, "--seed": seed, "--baud": baud, "--protocol": protocol,
                   "--tick-hz": tick_hz, "--state": state, "--trace": trace,
                   "--log-level": log_level}
        for option, value in options.items():
            if value is not None:
                argv += [option, os.fspath(value) if isinstance(value, os.PathLike) else str(value)]
        for directory in models:
            argv += ["--models", os.fspath(directory)]
        argv += list(args)
        self.process: DaemonProcess | None = None
        self.control: Control | None = None
        try:
            self.process = DaemonProcess(
                argv, binary=binary, timeout=timeout,
                ports=_config_port_count(config) if config is not None else 1)
            self.ports: dict[str, PortInfo] = {
                line["port"]: PortInfo(line["port"], line["pty"], line["link"], line["servos"])
                for line in self.process.ready}
            self.control = Control(self.process.ready[0]["control"])
        except BaseException:
            self.stop()
            raise

    def port(self, name: str | None = None) -> PortInfo:
        """The port called `name`, or the first one."""
        if name is None:
            return next(iter(self.ports.values()))
        return self.ports[name]

    @property
    def link(self) -> str:
        """The first port's stable link (the path a controller opens)."""
        return self.port().link

    @property
    def pty(self) -> str:
        """The first port's pseudo-terminal."""
        return self.port().pty

    def client(self, port: str | None = None, **options) -> Client:
        """A protocol client (dxlemu.protocol.Client) opened on a port's link; `options` go to
        Client (baud, protocol, timeout)."""
        return Client(self.port(port).link, **options)

    @property
    def stderr(self) -> str:
        """What the daemon wrote to stderr so far."""
        return self.process.stderr() if self.process is not None else ""

    @property
    def running(self) -> bool:
        """True while the daemon runs."""
        return self.process is not None and self.process.running

    def stop(self, timeout: float = 5.0) -> int | None:
        """Stops the daemon: the `shutdown` command, then SIGTERM, then SIGKILL, each given
        `timeout` seconds; removes the temporary directory. Returns the exit status (0 after a
        clean stop). Safe to call more than once. With $DXLEMU_CHECK_EXIT=1 the first call
        raises DaemonError as `DaemonProcess.stop` does."""
        code = None
        try:
            if self.process is not None:
                if self.control is not None and self.process.running:
                    try:
                        self.control.shutdown()
                        self.process.wait(timeout * timeout_scale())
                    except (ControlError, OSError, ValueError, subprocess.TimeoutExpired):
                        pass
                code = self.process.stop(timeout)
        finally:
            if self.control is not None:
                self.control.close()
            self._dir.cleanup()
        return code

    def __enter__(self) -> Emulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
