#!/usr/bin/env python3
"""Reliability: the control socket under abuse, while well-behaved clients keep working.

    python3 scripts/reliability/control_abuse.py [--quick]

docs/control-api.md promises that every request line gets exactly one reply, that bad requests
never close the connection or stop the daemon, and that a line over 64 KiB is refused and
skipped. While a well-behaved control client (get and set, checked) and a bus client (Ping, Read,
Write over the PTY, checked) run, this script:

1. sends 10,000 malformed requests of many kinds on one connection (not JSON, JSON that is not an
   object, no or a wrong `cmd`, unknown commands and fields, arguments of the wrong type or out of
   range, lines over the limit up to 1 MiB, binary garbage, deep nesting, invalid UTF-8, empty
   lines, scenario.load of a FIFO or a device): each must get an error reply (`"ok": false`, a
   message, the request's `id` echoed when it had one) that is valid UTF-8 JSON, or none for an
   empty line, and a valid request after them on the same connection must still succeed;
2. connects clients that leave mid-line (half a request, then close or half-close), that leave
   without reading their replies, or that send and never read until the socket is full;
3. floods from 50 connections at once, each pipelining valid and malformed requests and checking
   every reply, in order.

The well-behaved clients' every request must be answered correctly; their latency percentiles
are reported alone (baseline) and under abuse. The daemon runs under manual timing, so that a
bus reply made late by the load is sent rather than dropped: the bus client's check is about
the control socket's abuse, not the machine's. At the end the daemon must run, answer both
ways, hold as many file descriptors as before and stop cleanly. Exit status 0 when all holds,
1 (with `FAILED: ...`) when not.
"""
from __future__ import annotations

import json
import multiprocessing
import os
import random
import socket
import threading
import time
from typing import Callable

from common import (Failure, check, fd_targets, latency_ms, open_fds, parser, rss_kib, run,
                    summary)
from dxlemu import Client, Control, ControlError, Emulator

LINE_LIMIT = 65536
ANY_ID = object()  # the reply's id is not checked (the request's may not have parsed)
NO_REPLY = object()  # an empty line: ignored, no reply
WELL_BEHAVED_PAUSE_S = 0.001  # between the well-behaved clients' requests: latency, not load
FLOOD_CLIENTS = 50
FLOOD_BATCH = 10
REAP_TIMEOUT_S = 5.0  # for the daemon to close what its clients closed


# Malformed requests: each generator returns (line without its newline, the id the reply must
# carry: a value, None, ANY_ID, or NO_REPLY).

def _obj(rng: random.Random, **fields) -> tuple[bytes, int]:
    """A JSON object request with a random id, and that id."""
    ident = rng.randrange(1 << 31)
    return json.dumps({"id": ident, **fields}).encode(), ident


def not_json(rng: random.Random):
    text = rng.choice([b"{not json", b"hello", b'{"id": 1, "cmd": "help"', b"}", b"[1, 2",
                       b'{"cmd": help}', b"{'cmd': 'help'}", b'{"cmd": "help",}', b"   ",
                       b'{"id": 01, "cmd": "help"}', b'{"cmd": "help"} trailing',
                       b'{"cmd": NaN}', b'{"cmd": Infinity}', b'{"id": 1e400, "cmd": "x"}'])
    return text, None if text != b'{"id": 1e400, "cmd": "x"}' else ANY_ID


def not_an_object(rng: random.Random):
    return rng.choice([b"[]", b"42", b'"help"', b"null", b"true", b'[{"cmd": "help"}]',
                       b"-0", b"1.5e3"]), None


def bad_cmd(rng: random.Random):
    cmd = rng.choice([None, 5, ["help"], {"a": 1}, "", "gett", "HELP", "help ", "fault",
                      "x" * rng.randrange(1, 30000), "\u00e9\u4e2d\U0001F600", "shutdown\u0000"])
    if rng.random() < 0.2:
        ident = rng.randrange(1 << 31)
        return json.dumps({"id": ident}).encode(), ident  # no cmd at all
    return _obj(rng, cmd=cmd)


def unknown_field(rng: random.Random):
    cmd = rng.choice(["list", "help", "stats", "clock.now", "fault.list", "fault.clear"])
    return _obj(rng, cmd=cmd, **{rng.choice(["foo", "Port", "servo ", ""]): rng.randrange(9)})


def wrong_argument(rng: random.Random):
    """Arguments of the wrong type or out of range, for commands that would otherwise act."""
    fields = rng.choice([
        {"cmd": "get", "servo": "1", "item": "id"},
        {"cmd": "get", "servo": 1.5, "item": "id"},
        {"cmd": "get", "servo": -1, "item": "id"},
        {"cmd": "get", "servo": 2 ** 70, "item": "id"},
        {"cmd": "get", "servo": True, "item": "id"},
        {"cmd": "get", "servo": 1, "item": 5},
        {"cmd": "get", "servo": 1, "item": None},
        {"cmd": "get", "servo": 99, "item": "id"},
        {"cmd": "get", "servo": 1, "item": "present_temp"},
        {"cmd": "get", "servo": 1, "address": 9999, "size": 4},
        {"cmd": "get", "servo": 1, "address": 0, "size": 5},
        {"cmd": "get", "servo": 1},
        {"cmd": "get", "port": "nope", "servo": 1, "item": "id"},
        {"cmd": "set", "servo": 1, "item": "led", "value": "1"},
        {"cmd": "set", "servo": 1, "item": "led", "value": 1.5},
        {"cmd": "set", "servo": 1, "item": "led", "value": 2 ** 64},
        {"cmd": "set", "servo": 1, "item": "led"},
        {"cmd": "set", "servo": 1, "item": "present_temperature", "value": 300},
        {"cmd": "set", "servo": 1, "item": "present_temperature", "value": -1},
        {"cmd": "condition.set", "servo": 1, "blocked": "yes"},
        {"cmd": "condition.set", "servo": 1, "supply_voltage": 1000},
        {"cmd": "condition.set", "servo": 1, "ambient_temperature": "hot"},
        {"cmd": "clock.step", "ms": -10},
        {"cmd": "clock.step", "ms": 10, "ns": 5},  # exactly one of ms, us, ns
        {"cmd": "clock.step", "ms": "10"},
        {"cmd": "fault.add", "rule": "x"},
        {"cmd": "fault.add", "rule": {}},
        {"cmd": "fault.add", "rule": {"action": "nope"}},
        {"cmd": "fault.add", "rule": {"action": "drop_reply", "match": {"servos": [300]}}},
        {"cmd": "fault.remove", "rule": "a"},
        {"cmd": "fault.remove", "rule": 123456},
        {"cmd": "servo.detach", "servo": 42},
        {"cmd": "servo.attach", "servo": 1},  # attached already
        {"cmd": "trace.subscribe", "port": 5},
        {"cmd": "stats", "port": "nope"},
        {"cmd": "scenario.load"},
        {"cmd": "scenario.load", "file": "/nonexistent/scenario.json"},
        {"cmd": "scenario.load", "scenario": {"steps": [{"at_ms": -1, "cmd": "help"}]}},
        {"cmd": "scenario.load", "scenario": {"steps": [{"at_ms": 0, "cmd": "shutdown"},
                                                        {"at_ms": 0, "cmd": "nope"}]}},
    ])
    return _obj(rng, **fields)


def over_the_limit(rng: random.Random):
    """A line past 64 KiB, now and then far past it (1 MiB): refused, skipped to its newline."""
    size = rng.choice([LINE_LIMIT + 1, LINE_LIMIT + rng.randrange(2, 100_000), 1 << 20])
    if rng.random() < 0.5:
        return b'{"cmd": "help", "pad": "' + b"a" * size + b'"}', None
    return bytes(rng.randrange(0x20, 0x7F) for _ in range(64)) * (size // 64 + 1), None


def binary_garbage(rng: random.Random):
    """Random bytes (NUL and 0x80 ~ 0xFF included) up to 4 KiB, without a newline."""
    garbage = rng.randbytes(rng.randrange(1, 4096)).replace(b"\n", b"\x00")
    if garbage.strip(b" \t\r") == b"":
        garbage += b"\x01"  # blank would be an empty line: no reply
    return garbage, None


def empty_line(rng: random.Random):
    return rng.choice([b"", b"\r"]), NO_REPLY


def deep_nesting(rng: random.Random):
    """Nesting far past what a request needs, within the line limit (so it is parsed)."""
    depth = rng.choice([200, 1000, 10_000, 32_000])
    shape = rng.choice(["array", "object", "id", "unclosed"])
    if shape == "array":
        return b"[" * depth + b"]" * depth, None
    if shape == "object":
        return b'{"a":' * depth + b"1" + b"}" * depth, None
    if shape == "id":  # an id that, echoed, would nest as deep
        return b'{"cmd": "nope", "id": ' + b"[" * depth + b"]" * depth + b"}", ANY_ID
    return b"[" * depth, None


def invalid_utf8(rng: random.Random):
    return rng.choice([b'{"cmd": "\xff\xfe"}', b'{"cmd": "help", "id": "\xc3\x28"}',
                       b'{"cmd": "\xc0\xaf"}', b'{"cmd": "\xed\xa0\x80"}',
                       b'\xef\xbb\xbf{"cmd": 1}', b'{"cmd": "\\ud800"}', b'{"cmd": "\\udc00x"}',
                       b'{"cmd": "\xf8\x88\x80\x80\x80"}', b'{"cmd": "\x00"}',
                       b'{"cmd\x80": "help"}']), ANY_ID


# Files scenario.load must refuse without reading: a running daemon reading a FIFO would block
# until a writer came (bus and control API stopped), /dev/zero would never end. main() adds a
# FIFO of its own.
NOT_SCENARIO_FILES = ["/dev/zero", "/", "/dev/null"]


def not_a_scenario_file(rng: random.Random):
    return _obj(rng, cmd="scenario.load", file=rng.choice(NOT_SCENARIO_FILES))


KINDS: dict[str, Callable] = {
    "not_json": not_json, "not_an_object": not_an_object, "bad_cmd": bad_cmd,
    "unknown_field": unknown_field, "wrong_argument": wrong_argument,
    "over_the_limit": over_the_limit, "binary_garbage": binary_garbage,
    "empty_line": empty_line, "deep_nesting": deep_nesting, "invalid_utf8": invalid_utf8,
    "not_a_scenario_file": not_a_scenario_file,
}
# over_the_limit lines are up to 1 MiB: fewer of them keep the run short.
WEIGHTS = {"over_the_limit": 0.3, "deep_nesting": 0.5}


def check_error_reply(reply: dict, expected_id, what: str) -> None:
    """An error reply, with the id expected."""
    check(isinstance(reply, dict) and reply.get("ok") is False and
          isinstance(reply.get("error"), str) and reply["error"],
          f"{what}: not an error reply: {str(reply)[:300]}")
    if expected_id is not ANY_ID:
        check(reply.get("id") == expected_id,
              f"{what}: reply id {str(reply.get('id'))[:80]}, expected {expected_id}")


def read_reply(control: Control, what: str) -> dict:
    """The next reply line, as JSON; Failure when none comes or it is not UTF-8 JSON."""
    try:
        return control.reply()
    except ControlError as error:
        raise Failure(f"{what}: {error}") from error
    except ValueError as error:
        raise Failure(f"{what}: the reply is not valid UTF-8 JSON: {error}") from error


def still_usable(control: Control, what: str) -> None:
    """A valid request on the connection succeeds."""
    control.send_line(b'{"id": "probe", "cmd": "help"}')
    reply = read_reply(control, what)
    check(reply.get("id") == "probe" and reply.get("ok") is True and "help" in reply["result"],
          f"{what}: a valid request after malformed ones failed: {str(reply)[:300]}")


def malformed_requests(path: str, count: int, rng: random.Random, tally: dict[str, int]) -> None:
    """`count` malformed requests on one connection, each checked, the connection probed with a
    valid request every 50 and after an empty line."""
    names = list(KINDS)
    weights = [WEIGHTS.get(name, 1.0) for name in names]
    with Control(path, timeout=30.0) as control:
        for index in range(count):
            kind = rng.choices(names, weights)[0]
            line, expected_id = KINDS[kind](rng)
            tally[kind] = tally.get(kind, 0) + 1
            what = f"malformed request {index} ({kind}, {line[:60]!r}...)"
            control.send_line(line)
            if expected_id is NO_REPLY:
                still_usable(control, what)  # the probe's reply must be the next line
                continue
            check_error_reply(read_reply(control, what), expected_id, what)
            if index % 50 == 49:
                still_usable(control, what)
        still_usable(control, "after every malformed request")


def leave_mid_line(path: str, count: int, rng: random.Random, tally: dict[str, int]) -> None:
    """Clients that go away in the middle of things."""
    full = b'{"id": 1, "cmd": "get", "servo": 1, "item": "present_position"}'
    for _ in range(count):
        kind = rng.choice(["half_then_close", "half_then_half_close", "connect_close",
                           "no_read_close", "big_partial_close"])
        tally[kind] = tally.get(kind, 0) + 1
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
            sock.settimeout(10.0)
            sock.connect(path)
            if kind == "half_then_close":
                sock.sendall(full[:rng.randrange(1, len(full))])
            elif kind == "half_then_half_close":
                # docs: a half-close gets the replies to complete lines; the unfinished last line
                # is dropped, then the daemon closes.
                sock.sendall(full + b"\n" + full[:rng.randrange(1, len(full))])
                sock.shutdown(socket.SHUT_WR)
                received = b""
                while chunk := sock.recv(65536):
                    received += chunk
                lines = received.split(b"\n")
                check(len(lines) == 2 and lines[1] == b"" and json.loads(lines[0])["ok"],
                      f"half-closed client: expected one reply then EOF, got {received[:300]!r}")
            elif kind == "no_read_close":
                sock.sendall((full + b"\n") * rng.randrange(1, 50))
            elif kind == "big_partial_close":
                sock.sendall(b'{"cmd": "help", "pad": "' + b"x" * rng.randrange(1000, 200_000))


def never_reads(path: str, lines: int, tally: dict[str, int], name: str) -> None:
    """Sends `lines` requests without reading a reply (until the socket stays full for a
    second), then closes: the daemon must neither block nor hoard memory for it."""
    request = b'{"cmd": "list"}\n'
    sent = 0
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.settimeout(1.0)
        sock.connect(path)
        try:
            for _ in range(lines):
                sock.sendall(request)
                sent += 1
        except socket.timeout:
            pass  # the daemon stopped reading from us: back-pressure, as it should
    tally[name] = sent


def flood_client(path: str, requests: int, seed: int) -> None:
    """One of the flooding clients: batches of pipelined requests (valid and malformed mixed),
    every reply checked in order."""
    rng = random.Random(seed)
    with Control(path, timeout=60.0) as control:
        for first in range(0, requests, FLOOD_BATCH):
            batch = []
            for ident in range(first, min(requests, first + FLOOD_BATCH)):
                kind = rng.choice(["help", "stats", "get", "bad"])
                fields = {"help": {"cmd": "help"}, "stats": {"cmd": "stats"},
                          "get": {"cmd": "get", "servo": 2, "item": "model_number"},
                          "bad": {"cmd": "get", "servo": 2, "item": "nope"}}[kind]
                batch.append((ident, kind))
                control.send_line(json.dumps({"id": ident, **fields}).encode())
            for ident, kind in batch:
                reply = read_reply(control, f"flood client {seed}, request {ident}")
                check(reply.get("id") == ident,
                      f"flood client {seed}: reply {reply.get('id')} to request {ident}")
                check(reply.get("ok") is (kind != "bad"),
                      f"flood client {seed}, request {ident} ({kind}): {str(reply)[:300]}")
                if kind == "get":
                    check(reply["result"]["value"] == 1020, f"flood: model number {reply}")


class Worker(threading.Thread):
    """Runs `body` in a thread, keeping its failure for the main thread."""

    def __init__(self, body: Callable[[], None], name: str):
        super().__init__(name=name, daemon=True)
        self.body = body
        self.error: BaseException | None = None
        self.start()

    def run(self) -> None:
        try:
            self.body()
        except BaseException as error:  # noqa: BLE001  reported by the main thread
            self.error = error

    def result(self) -> None:
        """Joins; re-raises the thread's failure."""
        self.join()
        if self.error is not None:
            if isinstance(self.error, Failure):
                raise Failure(f"{self.name}: {self.error}")
            raise Failure(f"{self.name}: {self.error!r}")


def control_loop(path: str, seed: int, ready, stop, results) -> None:
    """The well-behaved control client: set and get of LED on servo 2, get of servo 1's model
    number, each answer checked, from when it sets `ready` until `stop` is set. Puts
    (latencies, failure or None) in `results`."""
    rng, latencies = random.Random(seed), []
    try:
        with Control(path, timeout=30.0) as control:
            ready.set()
            while not stop.is_set():
                value = rng.randrange(2)
                for call in (lambda: control.set(2, "led", value) == value,
                             lambda: control.get(2, "led") == value,
                             lambda: control.get(1, "model_number") == 1020):
                    start = time.monotonic()
                    check(call(), "a well-behaved control request got a wrong answer")
                    latencies.append(time.monotonic() - start)
                time.sleep(WELL_BEHAVED_PAUSE_S)
    except Exception as error:  # noqa: BLE001  reported by the parent
        results.put((latencies, f"well-behaved control client: {error!r}"))
        return
    results.put((latencies, None))


def bus_loop(link: str, seed: int, ready, stop, results) -> None:
    """The well-behaved bus client: Ping, Write and Read back of Profile Velocity on servo 3,
    each answer checked; otherwise as control_loop."""
    rng, latencies = random.Random(seed), []
    try:
        with Client(link, timeout=5.0) as client:
            ready.set()
            while not stop.is_set():
                value = rng.randrange(32768)
                steps = ((lambda: client.ping(3),
                          lambda r: r.error == 0 and r.value & 0xFFFF == 1020),
                         (lambda: client.write_int(3, 112, value, 4), lambda r: r.error == 0),
                         (lambda: client.read(3, 112, 4),
                          lambda r: r.error == 0 and r.value == value))
                for call, good in steps:
                    start = time.monotonic()
                    reply = call()
                    check(good(reply), f"a well-behaved bus request got a wrong answer: {reply}")
                    latencies.append(time.monotonic() - start)
                time.sleep(WELL_BEHAVED_PAUSE_S)
    except Exception as error:  # noqa: BLE001  reported by the parent (CommError included)
        results.put((latencies, f"well-behaved bus client: {error!r}"))
        return
    results.put((latencies, None))


class WellBehaved:
    """The control client and the bus client that must keep working throughout. Each runs in
    a process of its own, so that the abusers' threads, which share this interpreter, do not
    show in their latencies (seconds)."""

    def __init__(self, emulator: Emulator, rng: random.Random):
        context = multiprocessing.get_context("spawn")
        self.stop = context.Event()
        self.ready = [context.Event(), context.Event()]
        self.results = [context.Queue(), context.Queue()]
        self.processes = [
            context.Process(target=loop, args=(where, rng.randrange(1 << 30), ready, self.stop,
                                               results))
            for loop, where, ready, results in
            ((control_loop, emulator.control_path, self.ready[0], self.results[0]),
             (bus_loop, emulator.link, self.ready[1], self.results[1]))]
        for process in self.processes:
            process.start()
        for ready in self.ready:  # running before anything is measured against them
            check(ready.wait(timeout=30), "a well-behaved client did not start")
        self.control_latency: list[float] = []
        self.bus_latency: list[float] = []

    def finish(self) -> None:
        """Stops both clients; Failure if either failed."""
        self.stop.set()
        (self.control_latency, control_error), (self.bus_latency, bus_error) = (
            queue.get(timeout=60) for queue in self.results)
        for process in self.processes:
            process.join()
        for error in (control_error, bus_error):
            check(error is None, error or "")


def abuse(emulator: Emulator, args, rng: random.Random, tally: dict[str, int]) -> None:
    """Every kind of abuse at once; returns when all of it is done (each checked)."""
    path = emulator.control_path
    malformed = 500 if args.quick else 10_000
    leavers = 50 if args.quick else 1000
    flood = 20 if args.quick else 200
    workers = [Worker(lambda: malformed_requests(path, malformed, random.Random(rng.random()),
                                                 tally), "malformed requests"),
               Worker(lambda: leave_mid_line(path, leavers, random.Random(rng.random()), tally),
                      "clients leaving mid-line")]
    workers += [Worker(lambda n=n: never_reads(path, 5_000 if args.quick else 50_000, tally,
                                               f"never_reads_{n}"),
                       f"client that never reads {n}") for n in range(2)]
    workers += [Worker(lambda seed=seed: flood_client(path, flood, seed), f"flood client {seed}")
                for seed in range(FLOOD_CLIENTS)]
    for worker in workers:
        worker.result()
    tally["malformed_requests"] = malformed
    tally["clients_leaving_mid_line"] = leavers
    tally["flood_requests"] = flood * FLOOD_CLIENTS


def main() -> None:
    args = parser(__doc__.split("\n\n")[0]).parse_args()
    rng = random.Random(args.seed)
    baseline_s = 2.0 if args.quick else 10.0
    tally: dict[str, int] = {}
    with Emulator(timing="manual") as emulator:
        pid = emulator.process.proc.pid
        emulator.control.help()  # its connection accepted: counted in both figures
        fifo = os.path.join(emulator.directory, "scenario.fifo")
        os.mkfifo(fifo)
        NOT_SCENARIO_FILES.append(fifo)
        fds_before, targets_before = open_fds(pid), fd_targets(pid)
        rss_before = rss_kib(pid)
        baseline = WellBehaved(emulator, rng)
        time.sleep(baseline_s)
        baseline.finish()
        under_abuse = WellBehaved(emulator, rng)
        start = time.monotonic()
        try:
            abuse(emulator, args, rng, tally)
        finally:
            abuse_s = time.monotonic() - start
            under_abuse.finish()
        check(emulator.running, "the daemon exited")
        check(emulator.control.get(1, "model_number") == 1020, "control API: wrong answer")
        with emulator.client() as client:
            check(client.ping(1).error == 0, "the bus does not answer a Ping")
        # Closed connections are reaped from a handler of their own: wait for that, and no
        # longer than it takes; a descriptor leaked stays counted.
        deadline = time.monotonic() + REAP_TIMEOUT_S
        while (fds_after := open_fds(pid)) != fds_before and time.monotonic() < deadline:
            time.sleep(0.01)
        check(fds_after == fds_before,
              f"the daemon held {fds_before} descriptors before and {fds_after} after:\n"
              f"before {targets_before}\nafter  {fd_targets(pid)}")
        rss_after = rss_kib(pid)
        code = emulator.stop()
        check(code == 0, f"the daemon did not stop cleanly: exit status {code}\n{emulator.stderr}")
    kinds = ", ".join(f"{kind} {tally[kind]}" for kind in KINDS if kind in tally)
    leaving = ", ".join(f"{kind} {tally[kind]}" for kind in
                        ("half_then_close", "half_then_half_close", "connect_close",
                         "no_read_close", "big_partial_close") if kind in tally)
    summary("control_abuse", [
        ("abuse phase", f"{abuse_s:.1f} s"),
        ("malformed requests", f"{tally['malformed_requests']}, every one refused with an "
                               "error reply (none for empty lines), connection kept"),
        ("  by kind", kinds),
        ("clients leaving mid-line", f"{tally['clients_leaving_mid_line']} ({leaving})"),
        ("clients that never read", f"2, {tally['never_reads_0'] + tally['never_reads_1']} lines "
                                    "sent "
                                    "before the daemon stopped reading or they were done"),
        ("flood", f"{FLOOD_CLIENTS} clients at once, {tally['flood_requests']} requests, "
                  "every reply checked in order"),
        ("control client, alone", latency_ms(baseline.control_latency)),
        ("control client, under abuse", latency_ms(under_abuse.control_latency)),
        ("bus client, alone", latency_ms(baseline.bus_latency)),
        ("bus client, under abuse", latency_ms(under_abuse.bus_latency)),
        ("daemon fds", f"before {fds_before}, after {fds_after}"),
        ("daemon RSS", f"before {rss_before} KiB, after {rss_after} KiB"),
        ("at the end", "running, control and bus answer, clean stop (exit 0)"),
    ])


if __name__ == "__main__":
    run(main)
