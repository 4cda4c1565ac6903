#!/usr/bin/env python3
"""Reliability: random bytes between valid packets, at full speed, for minutes.

    python3 scripts/reliability/garbage_soak.py [--quick] [--minutes M]

A mixed bus (two XM430-W350 speaking Protocol 2.0, IDs 1 and 2, and an AX-12A speaking 1.0,
ID 10, all at 1 Mbps, --timing manual) gets, exchange after exchange, a chunk of random bytes
followed by a valid instruction packet (Ping, Read or Write of RAM items whose values the script
keeps track of) in one write; the script waits for the addressed servo's status and checks it:
error 0, and the data a real servo would return (model number, the value last written).

- Mode A (first half of the time): garbage without 0xFF. No header can start in it, so every
  valid packet must be answered, correctly.
- Mode B (second half): arbitrary bytes, one chunk in 40 with a header planted in it
  (FF FF, FF FF FD 00 with an ID and a LENGTH, a 1.0 header with a LENGTH), so the framers'
  recovery paths (bad check, impossible length, inter-byte timeout) all run. Which packets can be
  swallowed is decided exactly: the framers rescan every rejected byte (docs/wire.md), so a valid
  packet can be lost only inside a frame whose check passes. Such a frame has to start in the
  garbage; before each exchange the script looks at every header in garbage + packet, and when
  one makes a check-valid frame (a 1/256 chance for a 1.0 checksum, 1/65536 for a 2.0 CRC) it
  draws the garbage again (counted as "redrawn"). When a header in the garbage waits for more
  bytes than the write holds, it holds whatever follows it (the valid packet too, in its own
  protocol) until that protocol's inter-byte timeout (1.0: 100 ms, 2.0: 1.5 ms) drops it and
  the framer rescans its bytes: once the daemon has read the write, the script steps the clock
  1 ns past that timeout, once per such header, before it waits for the reply ("pauses"). So
  the reply comes, and the next exchange's bytes cannot complete a header left open; under
  manual timing no other time passes, so no other partial frame times out. A whole phantom frame whose check fails, addressed to a servo that
  listens in its protocol, earns that servo's Checksum Error (1.0) or CRC Error (2.0) status, but
  the valid packet follows it in the same write: on a half-duplex line the two collide, so the
  bus drops the error status and counts a collision (docs/bus.md "Collisions"). Those collisions
  are expected and counted, and only the valid packet's status may come. So in mode B too every
  valid packet must be answered, correctly.

Throughout, the daemon's RSS (VmRSS) is sampled once a second and must stay flat; the bus
counters (control API `stats`) must show exactly one frame and one reply per valid packet sent,
and one collision per dropped error status. Exit status 0
when all holds, 1 (with `FAILED: ...`) when not.
"""
from __future__ import annotations

import os
import random
import select
import time
from dataclasses import dataclass, field
from typing import Callable

from common import Failure, check, heard, latency_ms, parser, rss_kib, run, summary
from dxlemu import Emulator
from dxlemu.protocol import (PING, READ, STATUS, WRITE, Port, checksum1, crc16, packet1, packet2,
                             unstuff)

BAUD = 1_000_000
XM_IDS, AX_ID = (1, 2), 10
XM_MODEL, XM_FIRMWARE = 1020, 45
# Items each servo's Reads and Writes use: (address, size, highest value); RAM, no motion.
XM_ITEMS = {"led": (65, 1, 1), "profile_velocity": (112, 4, 32767)}
AX_ITEMS = {"led": (25, 1, 1), "moving_speed": (32, 2, 2047)}
XM_MODEL_NUMBER_ITEM = (0, 2)
MAX_GARBAGE = 48
PLANT_HEADER_CHANCE = 1 / 40
REPLY_TIMEOUT_S = 1.0  # replies come at once under manual timing: only a slow host waits
PAUSE_NS = {1: 100_000_001, 2: 1_500_001}  # just past each protocol's inter-byte timeout
# RSS may grow this much after the first tenth of a mode (allocator warm-up) before it counts
# as growing rather than flat.
RSS_GROWTH_LIMIT_KIB = 1024
MAX_FRAME2 = 4096  # the daemon's largest 2.0 packet (docs/wire.md)


@dataclass
class Tally:
    """What one mode did."""

    exchanges: int = 0
    garbage_bytes: int = 0
    planted: int = 0
    redrawn: int = 0
    pauses: int = 0
    dropped_errors: int = 0  # error statuses to damaged phantoms, dropped by the collision rule
    latencies: list[float] = field(default_factory=list)
    rss: list[int] = field(default_factory=list)


# The phantom frames garbage can make.

def phantom_at(stream: bytes, at: int) -> tuple:
    """What the framers make of a header at `stream[at]` (docs/wire.md): ("valid",) a frame
    whose check passes; ("bad", protocol, id) a whole frame whose check fails (the servo with
    that ID, if any, answers it with a CRC or Checksum Error status); ("waiting", protocol) a
    header whose declared length runs past the stream (it waits for more bytes or the inter-byte
    timeout); () not a header, or a length the framer refuses at once."""
    if stream[at:at + 4] == b"\xff\xff\xfd\x00":
        if len(stream) < at + 7:
            return ("waiting", 2)
        if stream[at + 4] in (0xFD, 0xFF):
            return ()
        length = stream[at + 5] | stream[at + 6] << 8
        end = at + 7 + length
        if length < 3 or 7 + length > MAX_FRAME2:
            return ()
        if end > len(stream):
            return ("waiting", 2)
        good = crc16(stream[at:end - 2]) == (stream[end - 2] | stream[end - 1] << 8)
        return ("valid",) if good else ("bad", 2, stream[at + 4])
    if stream[at:at + 2] != b"\xff\xff":
        return ()
    if len(stream) < at + 4:
        return ("waiting", 1)
    if stream[at + 2] == 0xFF or stream[at + 3] < 2:
        return ()
    end = at + 4 + stream[at + 3]
    if end > len(stream):
        return ("waiting", 1)
    good = checksum1(stream[at + 2:end - 1]) == stream[end - 1]
    return ("valid",) if good else ("bad", 1, stream[at + 2])


def phantoms(garbage: bytes, packet: bytes) -> list[tuple]:
    """The outcome of every header starting in `garbage` (its last byte included, with the
    packet's first bytes after it), framed over garbage + packet."""
    stream = garbage + packet
    found = []
    at = stream.find(b"\xff\xff")
    while 0 <= at < len(garbage):
        outcome = phantom_at(stream, at)
        if outcome:
            found.append(outcome)
        at = stream.find(b"\xff\xff", at + 1)
    return found


def random_garbage(rng: random.Random, arbitrary: bool, tally: Tally) -> bytes:
    """A chunk of garbage: without 0xFF (mode A), or arbitrary with a header planted now and
    then (mode B)."""
    size = rng.randint(0, MAX_GARBAGE)
    if not arbitrary:
        return bytes(rng.randrange(0xFF) for _ in range(size))
    chunk = bytearray(rng.randbytes(size))
    if rng.random() < PLANT_HEADER_CHANCE:
        tally.planted += 1
        header = rng.choice((
            b"\xff\xff",
            b"\xff\xff\xfd\x00",
            b"\xff\xff\xfd\x00" + bytes([rng.choice((1, 2, 0xFE, rng.randrange(256)))]) +
            rng.randrange(0, 5000).to_bytes(2, "little"),
            b"\xff\xff" + bytes([rng.choice((AX_ID, 0xFE, rng.randrange(256))),
                                 rng.randrange(256)]),
        ))
        where = rng.randint(0, len(chunk))
        chunk[where:where] = header
    return bytes(chunk)


# The valid packets and what must come back.

class Bus:
    """The client's view of the servos: the packets it sends and the replies it expects."""

    def __init__(self, rng: random.Random):
        self.rng = rng
        self.values = {(ident, name): 0 for ident in XM_IDS for name in XM_ITEMS}
        self.values.update({(AX_ID, name): 0 for name in AX_ITEMS})

    def next_exchange(self) -> tuple[int, int, bytes, bytes]:
        """(protocol, ID, packet, the status parameters expected) of a random exchange; a Write
        updates what later Reads expect."""
        ident = self.rng.choice((*XM_IDS, AX_ID))
        protocol, items = (2, XM_ITEMS) if ident in XM_IDS else (1, AX_ITEMS)
        build = packet2 if protocol == 2 else packet1
        width = 2 if protocol == 2 else 1  # address and length fields
        kind = self.rng.choice(("ping", "read", "read", "write", "write"))
        if kind == "ping":
            expected = (XM_MODEL.to_bytes(2, "little") + bytes([XM_FIRMWARE])
                        if protocol == 2 else b"")
            return protocol, ident, build(ident, PING), expected
        if kind == "read" and protocol == 2 and self.rng.random() < 0.2:
            address, size = XM_MODEL_NUMBER_ITEM
            params = address.to_bytes(width, "little") + size.to_bytes(width, "little")
            return protocol, ident, build(ident, READ, params), XM_MODEL.to_bytes(2, "little")
        name = self.rng.choice(sorted(items))
        address, size, highest = items[name]
        if kind == "read":
            params = address.to_bytes(width, "little") + size.to_bytes(width, "little")
            expected = self.values[(ident, name)].to_bytes(size, "little")
            return protocol, ident, build(ident, READ, params), expected
        value = self.rng.randint(0, highest)
        self.values[(ident, name)] = value
        params = address.to_bytes(width, "little") + value.to_bytes(size, "little")
        return protocol, ident, build(ident, WRITE, params), b""


SERVOS = {(2, ident) for ident in XM_IDS} | {(1, AX_ID)}  # (protocol, ID) that can answer


def parse_status(buffer: bytes) -> tuple[tuple[int, int, int, bytes], int] | None:
    """The first status packet in what the daemon sent, either protocol: ((protocol, ID,
    error, params), bytes used), or None while incomplete. The daemon sends nothing but whole
    status packets: any other byte is a Failure."""
    if len(buffer) < 4 and b"\xff\xff\xfd\x00".startswith(buffer):
        return None  # nothing yet, or the start of a header: wait for more
    if buffer[:4] == b"\xff\xff\xfd\x00":
        if len(buffer) < 7:
            return None
        end = 7 + (buffer[5] | buffer[6] << 8)
        if len(buffer) < end:
            return None
        check(crc16(buffer[:end - 2]) == (buffer[end - 2] | buffer[end - 1] << 8) and
              buffer[7] == STATUS, f"the daemon sent a bad 2.0 packet: {buffer[:end].hex(' ')}")
        return (2, buffer[4], buffer[8], unstuff(buffer[9:end - 2])), end
    if buffer[:2] == b"\xff\xff":
        if len(buffer) < 4:
            return None
        end = 4 + buffer[3]
        if len(buffer) < end:
            return None
        check(checksum1(buffer[2:end - 1]) == buffer[end - 1],
              f"the daemon sent a bad 1.0 packet: {buffer[:end].hex(' ')}")
        return (1, buffer[2], buffer[4], buffer[5:end - 1]), end
    raise Failure(f"the daemon sent bytes that begin no status packet: {buffer.hex(' ')}")


def exchange(port: Port, garbage: bytes, packet: bytes, reply: tuple[int, int, bytes],
             where: str, settle: Callable[[], None]) -> float:
    """Sends garbage + packet in one write, calls `settle`, then waits for the expected reply
    (protocol, ID, data, error 0) and for nothing else. Returns the time until it came."""
    protocol, ident, expected = reply
    port.flush_input()
    start = time.monotonic()
    port.write(garbage + packet)
    settle()
    deadline = start + REPLY_TIMEOUT_S
    received, elapsed = b"", None
    context = f"{packet.hex(' ')} after garbage {garbage.hex(' ')}"
    while elapsed is None:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([port.fd], [], [], left)[0]:
            raise Failure(f"{where}: no reply to {context}")
        received += os.read(port.fd, 4096)
        while (parsed := parse_status(received)) is not None:
            status, used = parsed
            received = received[used:]
            if elapsed is None and status == (protocol, ident, 0, expected):
                elapsed = time.monotonic() - start
            else:
                raise Failure(f"{where}: unexpected reply {status} to {context}; expected "
                              f"protocol {protocol} ID {ident}, error 0, data {expected.hex(' ')}")
    return elapsed


def soak(emulator: Emulator, port: Port, bus: Bus, arbitrary: bool, seconds: float,
         rng: random.Random) -> Tally:
    """One mode for `seconds`: exchanges back to back, RSS sampled once a second."""
    tally = Tally()
    pid = emulator.process.proc.pid
    name = "mode B" if arbitrary else "mode A"
    end = time.monotonic() + seconds
    next_sample = time.monotonic()
    while time.monotonic() < end:
        if time.monotonic() >= next_sample:
            tally.rss.append(rss_kib(pid))
            next_sample += 1.0
        protocol, ident, packet, expected = bus.next_exchange()
        garbage = random_garbage(rng, arbitrary, tally)
        outcomes = phantoms(garbage, packet)
        while ("valid",) in outcomes:  # a frame that could swallow the packet: not this garbage
            tally.redrawn += 1
            garbage = random_garbage(rng, arbitrary, tally)
            outcomes = phantoms(garbage, packet)
        check(arbitrary or not outcomes, f"mode A garbage made a header: {garbage.hex(' ')}")
        # Damaged phantom packets to a servo that listens earn its error status, which the
        # packet behind them in the same write collides with.
        tally.dropped_errors += sum(1 for outcome in outcomes
                                    if outcome[0] == "bad" and outcome[1:] in SERVOS)
        waits = [PAUSE_NS[outcome[1]] for outcome in outcomes if outcome[0] == "waiting"]
        tally.pauses += bool(waits)
        written = (emulator.control.stats()["dxl0"]["bytes_in"] + len(garbage) + len(packet)
                   if waits else 0)

        def settle() -> None:
            """Lets each header left open time out, once the daemon has read the write."""
            if waits:
                heard(emulator.control, written)
                for _ in waits:
                    emulator.control.clock_step(ns=max(waits))
        tally.latencies.append(exchange(port, garbage, packet, (protocol, ident, expected),
                                        f"{name}, exchange {tally.exchanges}", settle))
        tally.exchanges += 1
        tally.garbage_bytes += len(garbage)
    tally.rss.append(rss_kib(pid))
    check(emulator.running, f"{name}: the daemon exited")
    return tally


def check_rss_flat(tally: Tally, name: str) -> str:
    """RSS after the first tenth of the mode may not grow past the limit; returns the figures."""
    settled = tally.rss[len(tally.rss) // 10]
    growth = tally.rss[-1] - settled
    figures = (f"first {tally.rss[0]} KiB, last {tally.rss[-1]} KiB, max {max(tally.rss)} KiB "
               f"({len(tally.rss)} samples)")
    check(growth <= RSS_GROWTH_LIMIT_KIB,
          f"{name}: RSS grew by {growth} KiB after warm-up ({figures})")
    return figures


def main() -> None:
    options = parser(__doc__.split("\n\n")[0])
    options.add_argument("--minutes", type=float, default=4.0,
                         help="length of the whole soak, half per mode (default 4)")
    args = options.parse_args()
    seconds = 10.0 if args.quick else args.minutes * 60
    rng = random.Random(args.seed)
    with Emulator(servos=[f"xm430-w350:{XM_IDS[0]}-{XM_IDS[-1]}", f"ax-12a:{AX_ID}"],
                  timing="manual", baud=BAUD) as emulator:
        bus = Bus(rng)
        with Port(emulator.link, BAUD) as port:
            mode_a = soak(emulator, port, bus, False, seconds / 2, rng)
            stats_a = emulator.control.stats()["dxl0"]
            mode_b = soak(emulator, port, bus, True, seconds / 2, rng)
        stats = emulator.control.stats()["dxl0"]
        sent = mode_a.exchanges + mode_b.exchanges
        check(stats_a["frames"] == mode_a.exchanges and stats_a["replies"] == mode_a.exchanges,
              f"mode A: {mode_a.exchanges} packets sent, the bus counted {stats_a}")
        dropped = mode_a.dropped_errors + mode_b.dropped_errors
        check(stats["frames"] == sent and stats["replies"] == sent and
              stats["collisions"] == dropped,
              f"{sent} packets sent and {dropped} error statuses dropped in collisions expected, "
              f"the bus counted {stats}")
        rss_a, rss_b = check_rss_flat(mode_a, "mode A"), check_rss_flat(mode_b, "mode B")
        code = emulator.stop()
        check(code == 0, f"the daemon did not stop cleanly: exit status {code}\n{emulator.stderr}")
    rows = []
    for name, tally, rss in (("A (no 0xFF)", mode_a, rss_a), ("B (arbitrary)", mode_b, rss_b)):
        rows += [
            (f"mode {name}: exchanges", f"{tally.exchanges} in {seconds / 2:.0f} s "
                                        f"({tally.exchanges / (seconds / 2):.0f}/s), all answered "
                                        "correctly"),
            (f"mode {name}: garbage", f"{tally.garbage_bytes} bytes; headers planted "
                                      f"{tally.planted}, garbage redrawn {tally.redrawn}, "
                                      f"pauses {tally.pauses}, error statuses to damaged "
                                      f"phantom packets dropped in collisions "
                                      f"{tally.dropped_errors}"),
            (f"mode {name}: round trip", latency_ms(tally.latencies)),
            (f"mode {name}: RSS", rss),
        ]
    rows.append(("bus counters at the end", ", ".join(f"{key} {value}"
                                                      for key, value in stats.items())))
    summary("garbage_soak", rows)


if __name__ == "__main__":
    run(main)
