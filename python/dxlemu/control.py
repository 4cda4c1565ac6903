"""A client of dxlemu's control API: newline-delimited JSON over the daemon's Unix socket
(docs/control-api.md).

Each request gets one reply, in order. Event lines (objects with an "event" key, sent after
`trace.subscribe`) may arrive between replies: they are kept aside and read with `events()`.
"""
from __future__ import annotations

import collections
import json
import select
import socket
import time
from typing import Any

_CHUNK = 65536


class ControlError(Exception):
    """A request the daemon refused (its message), or a broken connection."""

    def __init__(self, message: str, reply: dict | None = None):
        super().__init__(message)
        self.reply = reply
        """The whole reply line, when there was one."""


def _without_none(**fields: Any) -> dict[str, Any]:
    """The fields that were given (arguments left at None are not sent)."""
    return {key: value for key, value in fields.items() if value is not None}


class Control:
    """A connection to the control socket at `path`; `timeout` (seconds) bounds each reply.
    Usable as a context manager."""

    def __init__(self, path: str, timeout: float = 5.0):
        self.path = path
        self.timeout = timeout
        self._sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._sock.settimeout(timeout)
        try:
            self._sock.connect(path)
        except BaseException:
            self._sock.close()
            raise
        self._buffer = b""
        self._next_id = 1
        self._events: collections.deque[dict] = collections.deque()

    # Lines on the wire.

    def send_line(self, line: bytes) -> None:
        """Sends one raw request line (the newline is added)."""
        self._sock.sendall(line + b"\n")

    def _read_line(self, deadline: float) -> dict | None:
        """The next line as JSON, or None when `deadline` (time.monotonic()) passes first."""
        while b"\n" not in self._buffer:
            left = max(0.0, deadline - time.monotonic())
            if not select.select([self._sock], [], [], left)[0]:
                return None
            chunk = self._sock.recv(_CHUNK)
            if not chunk:
                raise ControlError(f"the control socket {self.path} closed")
            self._buffer += chunk
        line, self._buffer = self._buffer.split(b"\n", 1)
        return json.loads(line)

    @staticmethod
    def _is_event(message: dict) -> bool:
        return isinstance(message, dict) and "event" in message

    def reply(self) -> dict:
        """The next reply line, keeping event lines that come before it for `events()`."""
        deadline = time.monotonic() + self.timeout
        while True:
            message = self._read_line(deadline)
            if message is None:
                raise ControlError(f"no reply from {self.path} within {self.timeout} s")
            if not self._is_event(message):
                return message
            self._events.append(message)

    def events(self, timeout: float = 0.0) -> list[dict]:
        """The event lines received so far; when there are none, waits up to `timeout` seconds
        for some."""
        deadline = time.monotonic() + timeout
        while True:
            message = self._read_line(time.monotonic() if self._events else deadline)
            if message is None:
                break
            if not self._is_event(message):
                raise ControlError(f"a reply nobody asked for: {message}", message)
            self._events.append(message)
        events = list(self._events)
        self._events.clear()
        return events

    # Requests.

    def request(self, cmd: str, **args: Any) -> dict:
        """Sends {"id": n, "cmd": cmd, ...args} and returns the whole reply (ok or not)."""
        request_id = self._next_id
        self._next_id += 1
        self.send_line(json.dumps({"id": request_id, "cmd": cmd, **args}).encode())
        reply = self.reply()
        if reply.get("id") != request_id:
            raise ControlError(f"reply to request {reply.get('id')} while waiting for {request_id}",
                               reply)
        return reply

    def call(self, cmd: str, **args: Any) -> Any:
        """The result of a request; raises ControlError with the daemon's message if refused."""
        reply = self.request(cmd, **args)
        if not reply.get("ok"):
            raise ControlError(f"{cmd}: {reply.get('error')}", reply)
        return reply.get("result")

    # One method per command.

    def help(self) -> list[str]:
        """The names of the commands this daemon offers."""
        return self.call("help")

    def list(self) -> dict:
        """Every port with its PTY and link, and every servo with its model and key state."""
        return self.call("list")

    def get(self, servo: int, item: str | None = None, *, port: str | None = None,
            address: int | None = None, size: int | None = None) -> int:
        """An item's value by key (`present_temperature`), or `size` bytes at `address` as an
        unsigned number in the model's byte order (little-endian on every DYNAMIXEL); device-side,
        without access rules."""
        return self.call("get", **_without_none(port=port, servo=servo, item=item,
                                                address=address, size=size))["value"]

    def set(self, servo: int, item: str | None = None, value: int | None = None, *,
            port: str | None = None, address: int | None = None, size: int | None = None) -> int:
        """Sets an item by key (or by `address` and `size`) to `value`, as a bus Write would
        where one could, else forced device-side (docs/control-api.md). Returns the value."""
        if value is None:
            raise TypeError("set needs a value")
        return self.call("set", **_without_none(port=port, servo=servo, item=item, value=value,
                                                address=address, size=size))["value"]

    def stats(self, port: str | None = None) -> dict:
        """The bus counters of every port (or of `port`), by port name."""
        return self.call("stats", **_without_none(port=port))

    def condition_set(self, servo: int | None = None, *, port: str | None = None,
                      **conditions: Any) -> dict:
        """Sets the world around a servo (every servo of the port when `servo` is None):
        ambient_temperature (°C), supply_voltage (V), external_load (N·m), blocked (bool)."""
        return self.call("condition.set", **_without_none(port=port, servo=servo), **conditions)

    def detach(self, servo: int, *, port: str | None = None) -> dict:
        """Unplugs a servo: it hears and answers nothing and gives no torque."""
        return self.call("servo.detach", **_without_none(port=port, servo=servo))

    def attach(self, servo: int, *, port: str | None = None) -> dict:
        """Plugs a servo back in: it powers on (a reboot) and is silent for its boot time."""
        return self.call("servo.attach", **_without_none(port=port, servo=servo))

    def power_cycle(self, servo: int, *, port: str | None = None) -> dict:
        """Switches a plugged-in servo off and on: a reboot, then its boot time."""
        return self.call("servo.power_cycle", **_without_none(port=port, servo=servo))

    def reboot(self, servo: int, *, port: str | None = None) -> dict:
        """The Reboot instruction, as a tool sends it: RAM reset, EEPROM kept, then its boot time."""
        return self.call("servo.reboot", **_without_none(port=port, servo=servo))

    def factory_reset(self, servo: int, *, keep: str | None = None,
                      port: str | None = None) -> dict:
        """The Factory Reset instruction; `keep` is "none" (default), "id" or "id_baud"."""
        return self.call("servo.factory_reset",
                         **_without_none(port=port, servo=servo, keep=keep))

    def clock_now(self) -> int:
        """Simulated time since the daemon started, in nanoseconds."""
        return self.call("clock.now")["ns"]

    def clock_step(self, *, ms: float | None = None, us: float | None = None,
                   ns: int | None = None) -> int:
        """With `--timing manual`: moves simulated time forward by exactly one of `ms`, `us`
        or `ns`; returns the new time in nanoseconds."""
        return self.call("clock.step", **_without_none(ms=ms, us=us, ns=ns))["ns"]

    def fault_add(self, rule: dict) -> int:
        """Adds a fault rule ({"action": ..., "match": {...}, ...}); returns its ID."""
        return self.call("fault.add", rule=rule)["rule"]

    def fault_list(self) -> list[dict]:
        """Every rule: {"id", "rule", "matched", "fired"}."""
        return self.call("fault.list")

    def fault_remove(self, rule_id: int) -> None:
        """Removes one rule: its effect ends (an injected hardware error stops being present)."""
        self.call("fault.remove", rule=rule_id)

    def fault_clear(self) -> None:
        """Removes every rule."""
        self.call("fault.clear")

    def trace_subscribe(self, port: str | None = None) -> Any:
        """From now on this connection receives every packet of `port` (or of every port) as
        {"event": "trace", ...} lines, read with `events()`."""
        return self.call("trace.subscribe", **_without_none(port=port))

    def trace_unsubscribe(self) -> None:
        """Stops this connection's trace events."""
        self.call("trace.unsubscribe")

    def physics(self, joint: str | None = None) -> dict:
        """The physics world now: its joints (position, velocity, the forces on each, the servo
        driving it) and the bodies pushed; with `joint`, that joint's entry alone."""
        return self.call("physics", **_without_none(joint=joint))

    def physics_apply(self, *, joint: str | None = None, body: str | None = None,
                      torque_nm: float | list[float] | None = None,
                      force_n: list[float] | None = None) -> dict:
        """Pushes a joint (`torque_nm`, a number) or a body (`force_n` and/or `torque_nm`,
        [x, y, z] in world coordinates) from now on; zero removes the push."""
        return self.call("physics.apply", **_without_none(joint=joint, body=body,
                                                           torque_nm=torque_nm, force_n=force_n))

    def hand(self, port: str | None = None) -> list[dict]:
        """Every joint a virtual hand holds (docs/hands.md): its servo, source, value now,
        whether its play has ended."""
        return self.call("hand", **_without_none(port=port))

    def hand_play(self, file: str, *, port: str | None = None, loop: bool | None = None,
                  speed: float | None = None, start_s: float | None = None,
                  interpolation: str | None = None,
                  force_limit_nm: float | None = None) -> dict:
        """Plays a trajectory file (or a shipped trajectory by name) on the joints it names."""
        return self.call("hand.play", **_without_none(
            file=file, port=port, loop=loop, speed=speed, start_s=start_s,
            interpolation=interpolation, force_limit_nm=force_limit_nm))

    def hand_sweep(self, *, port: str | None = None, joints: list[str | int] | None = None,
                   order: str | None = None, speed_deg_s: float | None = None,
                   to: str | None = None, force_limit_nm: float | None = None) -> dict:
        """Sweeps the joints through their ranges as LeRobot's calibration asks; `to="middle"`
        only brings them to the middle."""
        return self.call("hand.sweep", **_without_none(
            port=port, joints=joints, order=order, speed_deg_s=speed_deg_s, to=to,
            force_limit_nm=force_limit_nm))

    def hand_move(self, joint: str | int, position: float, *, port: str | None = None,
                  units: str | None = None, duration_s: float | None = None,
                  force_limit_nm: float | None = None) -> dict:
        """Eases one joint to `position` (degrees, or raw with units="raw")."""
        return self.call("hand.move", **_without_none(
            joint=joint, position=position, port=port, units=units, duration_s=duration_s,
            force_limit_nm=force_limit_nm))

    def hand_stop(self, *, port: str | None = None,
                  joints: list[str | int] | None = None) -> dict:
        """The hands of `joints` (default all of the port's) let go."""
        return self.call("hand.stop", **_without_none(port=port, joints=joints))

    def shutdown(self) -> None:
        """Stops the daemon as SIGTERM would, after the reply."""
        self.call("shutdown")

    def close(self) -> None:
        """Closes the connection (idempotent)."""
        self._sock.close()

    def __enter__(self) -> Control:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
