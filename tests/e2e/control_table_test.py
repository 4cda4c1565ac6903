"""End-to-end: every model of models/catalog.json, over each protocol it speaks, read whole
over a real PTY and compared with its model file; every read-only item refuses a write.

One daemon serves every model at once (docs/config.md): one port per protocol and baud rate,
each model on it once (twice for a dual-axis model, one servo per axis) under IDs 1, 2, 3...
Models whose default protocol is 2.0 and that speak 1.0 too are on a 1.0 port with the config's
`"protocol": 1`, which sets their Protocol Type (Protocol Version on MX-64/106(2.0)). Every
other item starts at the model's factory value, so the table must read:

- `initial` (or the `initial_from` item's), except ID (the ID given) and, on the 1.0 ports of
  2.0-default models, the protocol item (1);
- for live readings (what the motion model writes: Present/Sensed values, MX 1.0 Current,
  Realtime Tick, Moving, Moving Status, the trajectories) only a value within the item's range
  (its whole width where the file gives none): what they read at rest, model by model, is the
  subject of the rest-value unit test over all models, not of this one.

Reads take as few packets as the protocol allows: on 2.0 one Bulk Read per port for the whole
tables; on 1.0 one Bulk Read for the models that answer it (protocol1.md "Bulk Read": MX,
MX(2.0) and X) and one Read per model for the others, each reply at most 253 data bytes and
only the items a one-byte address reaches. Then each read-only item gets a Write, which must be
refused: 2.0 with Access Error 0x07 (protocol2.md "Error"); 1.0 with the Range Error bit 0x08,
dxlemu's choice where protocol1.md defines no access error (docs/control-table.md). A second
read of every table must equal the first byte for byte: under `--timing manual` nothing moves
between them, so any difference is a refused write that changed something.
"""
from __future__ import annotations

import json
import os
import tempfile
import unittest
from pathlib import Path
from typing import NamedTuple

from dxl_client import BAUD, Control, DaemonProcess, Port, packet1, packet2, timeout_scale

MODELS_DIR = Path(__file__).resolve().parents[2] / "models"

READ, WRITE, BULK_READ = 0x02, 0x03, 0x92
BROADCAST = 0xFE

# What a refused Write of a read-only item answers, per protocol (module docstring).
ACCESS_ERROR_V2 = 0x07
RANGE_ERROR_BIT_V1 = 0x08

# Protocol 1.0 limits: one-byte addresses and lengths; a status carries at most 253 data bytes
# (its LENGTH byte also counts the error and the checksum, docs/control-table.md "Reads");
# a Bulk Read packet's LENGTH (3 per device + 3) fits one byte.
V1_ADDRESS_SPACE = 256
V1_MAX_DATA = 253
V1_BULK_READ_MAX_DEVICES = (255 - 3) // 3
# Servos per 2.0 Bulk Read: one packet asks for at most this many whole tables, so a reply
# train stays a few kilobytes however many models the catalogue holds.
V2_BULK_READ_MAX_DEVICES = 16
V1_BULK_READ_FAMILIES = {"mx1", "mx2", "x"}  # protocol1.md "Bulk Read": MX, MX(2.0), X

# The keys Protocol Type is known by (config.md `servos[].protocol`).
PROTOCOL_ITEMS = ("protocol_type", "protocol_version")

MAX_ID = 252  # the highest ID a config gives a servo
BAUD_TOLERANCE = 0.03  # a servo hears a client within 3 % of its Baud Rate (docs/bus.md)
FALLBACK_BAUD = 1000000  # where a model's factory rate is not one termios offers
SETTLE_MS = 100  # lived at rest beyond its boot time before the first read
REPLY_TIMEOUT_S = 2.0  # replies come at once under manual timing: only a slow host waits
SILENCE_S = 0.05  # how long a servo that must not answer is given to answer anyway


def is_live(key: str) -> bool:
    """An item the motion model writes, whose value at rest is not this test's subject. MX 1.0
    `current` (68) is one although it is RW: the motor's current, 2048 at rest
    (control-tables/mx-64.md)."""
    return (key.startswith(("present_", "sensed_")) or key.endswith("_trajectory")
            or key in ("realtime_tick", "moving", "moving_status", "current"))


class Item(NamedTuple):
    """One item of a model file: where it is, whether a client may write it, its range (the
    item's whole width where the file gives none)."""

    key: str
    address: int
    size: int
    read_only: bool
    signed: bool
    low: int
    high: int
    values: tuple[int, ...] | None

    def decode(self, table: bytes) -> int:
        """Its value in a table read from address 0."""
        raw = table[self.address:self.address + self.size]
        return int.from_bytes(raw, "little", signed=self.signed)

    def in_range(self, value: int) -> bool:
        return self.low <= value <= self.high and (not self.values or value in self.values)


def item_of(entry: dict) -> Item:
    """The Item of an `items` entry of a model file (docs/model-format.md "Items")."""
    signed = bool(entry.get("signed"))
    bits = 8 * entry["size"]
    low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
    values = tuple(entry["values"]) if "values" in entry else None
    return Item(entry["key"], entry["address"], entry["size"], entry["access"] == "R", signed,
                entry.get("min", low), entry.get("max", high), values)


class Model(NamedTuple):
    """What this test needs of one model file."""

    name: str
    family: str
    protocols: tuple[int, ...]
    axes: int
    baud_rates: dict[int, int]  # Baud Rate item value -> bit/s
    default_baud_index: int
    boot_ms: int
    items: tuple[Item, ...]
    initial: dict[str, int]  # key -> factory value, `initial_from` resolved

    @property
    def answers_writes(self) -> bool:
        """Status Return Level 2 at the factory (the default where the model has no item)."""
        return self.initial.get("status_return_level", 2) >= 2


def load_models() -> list[Model]:
    """Every model of models/catalog.json, in catalog order."""
    with open(MODELS_DIR / "catalog.json", encoding="utf-8") as f:
        catalog = json.load(f)["models"]
    models = []
    for entry in catalog:
        with open(MODELS_DIR / entry["file"], encoding="utf-8") as f:
            spec = json.load(f)
        initial = {i["key"]: i["initial"] for i in spec["items"] if "initial" in i}
        copied = {i["key"]: i["initial_from"] for i in spec["items"] if "initial_from" in i}
        while copied:  # an item may copy one that copies another
            key = next(k for k, source in copied.items() if source in initial)
            initial[key] = initial[copied.pop(key)]
        models.append(Model(spec["name"], spec["family"], tuple(spec["protocols"]),
                            spec.get("axes", 1),
                            {b["index"]: b["bps"] for b in spec["baud_rates"]},
                            spec["default_baud_index"], spec["timing"]["boot_ms"],
                            tuple(item_of(i) for i in spec["items"]), initial))
    return models


class Servo(NamedTuple):
    """One servo (one axis) on a port, and what its table must read."""

    model: Model
    id: int
    protocol: int
    items: tuple[Item, ...]  # those this protocol's addresses reach
    expected: dict[str, int]

    @property
    def label(self) -> str:
        return f"{self.model.name} (ID {self.id}, Protocol {self.protocol}.0)"

    def spans(self) -> list[tuple[int, int]]:
        """(address, length) reads covering every item: the whole table at once in 2.0, pieces
        of at most 253 bytes in 1.0."""
        end = max(i.address + i.size for i in self.items)
        step = end if self.protocol == 2 else V1_MAX_DATA
        return [(start, min(step, end - start)) for start in range(0, end, step)]


def client_rate(bps: int) -> int | None:
    """The termios rate a client sets to be heard by a servo at `bps`, if any."""
    near = [rate for rate in BAUD if abs(rate - bps) <= BAUD_TOLERANCE * bps]
    return min(near, key=lambda rate: abs(rate - bps)) if near else None


class Bus(NamedTuple):
    """One port of the config: the protocol its client speaks, at which rate, and its servos."""

    name: str
    protocol: int
    rate: int
    config: list[dict]  # the port's servos entries
    servos: list[Servo]


def plan_buses(models: list[Model]) -> list[Bus]:
    """One port per (protocol, client rate), as many as the IDs need; every model on one port
    per protocol it speaks."""
    buses: dict[tuple[int, int], list[Bus]] = {}
    for protocol in (2, 1):
        for model in models:
            if protocol not in model.protocols:
                continue
            entry: dict = {"model": model.name}
            expected = dict(model.initial)
            rate = client_rate(model.baud_rates[model.default_baud_index])
            if rate is None:
                rate = FALLBACK_BAUD
                entry["baud"] = rate
                expected["baud_rate"] = next(index for index, bps in model.baud_rates.items()
                                             if client_rate(bps) == rate)
            if protocol != model.protocols[0]:
                entry["protocol"] = protocol
                for key in PROTOCOL_ITEMS:
                    if key in expected:
                        expected[key] = protocol
            group = buses.setdefault((protocol, rate), [])
            if not group or len(group[-1].servos) + model.axes > MAX_ID:
                group.append(Bus(f"p{protocol}-{rate}-{len(group)}", protocol, rate, [], []))
            bus = group[-1]
            ids = [len(bus.servos) + 1 + axis for axis in range(model.axes)]
            entry["ids"] = ids
            bus.config.append(entry)
            reachable = tuple(i for i in model.items
                              if protocol == 2 or i.address + i.size <= V1_ADDRESS_SPACE)
            for ident in ids:
                bus.servos.append(Servo(model, ident, protocol, reachable,
                                        {**expected, "id": ident}))
    return [bus for group in buses.values() for bus in group]


def flipped(value: int, item: Item) -> bytes:
    """The item's bytes with the lowest bit of `value` flipped: a value it does not hold."""
    return ((value ^ 1) & ((1 << (8 * item.size)) - 1)).to_bytes(item.size, "little")


class Wire:
    """A client on one port: reads whole tables, writes single items."""

    def __init__(self, port: Port, bus: Bus):
        self.port = port
        self.bus = bus

    def _status(self, timeout: float = REPLY_TIMEOUT_S):
        timeout *= timeout_scale()
        if self.bus.protocol == 2:
            return self.port.status2(timeout)
        return self.port.status1(timeout)

    def _packet(self, ident: int, instruction: int, params: bytes) -> bytes:
        make = packet2 if self.bus.protocol == 2 else packet1
        return make(ident, instruction, params)

    def _address(self, value: int) -> bytes:
        return value.to_bytes(2 if self.bus.protocol == 2 else 1, "little")

    def read_tables(self) -> tuple[dict[int, bytes], list[str]]:
        """Every servo's table (bytes from address 0), and what went wrong."""
        tables = {servo.id: bytearray() for servo in self.bus.servos}
        problems: list[str] = []
        if self.bus.protocol == 2:
            grouped, single = self.bus.servos, []
        else:
            grouped = [s for s in self.bus.servos if s.model.family in V1_BULK_READ_FAMILIES]
            single = [s for s in self.bus.servos if s.model.family not in V1_BULK_READ_FAMILIES]
        span_count = max((len(s.spans()) for s in grouped), default=0)
        for index in range(span_count):
            batch = [s for s in grouped if index < len(s.spans())]
            limit = V2_BULK_READ_MAX_DEVICES if self.bus.protocol == 2 else V1_BULK_READ_MAX_DEVICES
            for first in range(0, len(batch), limit):
                self._bulk_read(batch[first:first + limit], index, tables, problems)
        for servo in single:
            for address, length in servo.spans():
                self.port.write(self._packet(servo.id, READ,
                                             self._address(address) + self._address(length)))
                self._take(servo, length, tables, problems)
        return {ident: bytes(table) for ident, table in tables.items()}, problems

    def _bulk_read(self, servos: list[Servo], span: int, tables: dict[int, bytearray],
                   problems: list[str]) -> None:
        params = bytearray() if self.bus.protocol == 2 else bytearray([0x00])
        for servo in servos:
            address, length = servo.spans()[span]
            if self.bus.protocol == 2:
                params += bytes([servo.id]) + self._address(address) + length.to_bytes(2, "little")
            else:
                params += bytes([length, servo.id, address])
        self.port.write(self._packet(BROADCAST, BULK_READ, bytes(params)))
        for servo in servos:
            self._take(servo, servo.spans()[span][1], tables, problems)

    def _take(self, servo: Servo, length: int, tables: dict[int, bytearray],
              problems: list[str]) -> None:
        status = self._status()
        if status is None:
            problems.append(f"{servo.label}: no reply to a read of {length} bytes")
        elif status.id != servo.id or status.error != 0 or len(status.params) != length:
            problems.append(f"{servo.label}: a read of {length} bytes answered {status}")
        else:
            tables[servo.id] += status.params

    def write(self, servo: Servo, item: Item, data: bytes):
        self.port.write(self._packet(servo.id, WRITE, self._address(item.address) + data))
        return self._status(REPLY_TIMEOUT_S if servo.model.answers_writes else SILENCE_S)


def check_table(servo: Servo, table: bytes) -> list[str]:
    """Where `table` differs from what the servo's model file says it holds."""
    problems = []
    for item in servo.items:
        value = item.decode(table)
        if is_live(item.key):
            if not item.in_range(value):
                problems.append(f"{servo.label}: live reading {item.key}({item.address}) = "
                                f"{value}, outside {item.low} ~ {item.high}"
                                + (f" / {list(item.values)}" if item.values else ""))
        elif value != servo.expected[item.key]:
            problems.append(f"{servo.label}: {item.key}({item.address}) = {value}, the model "
                            f"file says {servo.expected[item.key]}")
    return problems


class EveryModelOverTheWireTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.models = load_models()
        cls.buses = plan_buses(cls.models)
        directory = tempfile.TemporaryDirectory()
        cls.addClassCleanup(directory.cleanup)
        cls.dir = directory.name
        config = {"description": "every model of models/catalog.json",
                  "ports": [{"name": bus.name, "link": os.path.join(cls.dir, bus.name),
                             "servos": bus.config} for bus in cls.buses]}
        path = os.path.join(cls.dir, "every-model.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(config, f)
        daemon = DaemonProcess(["--config", path, "--timing", "manual"], ports=len(cls.buses))
        cls.addClassCleanup(daemon.stop)
        cls.ready = daemon.ready
        control = Control(cls.ready[0]["control"])
        cls.addClassCleanup(control.close)
        # Past every model's power-on silence (boot time), then time stands still.
        boot_ms = max(model.boot_ms for model in cls.models)
        control.call("clock.step", ms=boot_ms + SETTLE_MS)

    def wire(self, bus: Bus) -> Wire:
        port = Port(os.path.join(self.dir, bus.name), bus.rate)
        self.addCleanup(port.close)
        return Wire(port, bus)

    def test_every_model_is_on_a_port_of_each_protocol_it_speaks(self):
        # Everything below, and the table test, holds for an empty catalogue or a servo whose
        # protocol reaches none of its items: neither may pass for coverage.
        self.assertGreater(len(self.models), 1)
        self.assertEqual([s.label for bus in self.buses for s in bus.servos if not s.items], [])
        served = {(line["port"], s["id"], s["model"]) for line in self.ready
                  for s in line["servos"]}
        planned = {(bus.name, s.id, s.model.name) for bus in self.buses for s in bus.servos}
        self.assertEqual(served, planned)
        # DYNAMIXEL's two packet protocols; Modbus RTU reads the same tables through registers,
        # which e2e.modbus and the unit tests of the register map cover.
        for model in self.models:
            self.assertEqual(sorted({b.protocol for b in self.buses
                                     for s in b.servos if s.model is model}),
                             sorted(p for p in model.protocols if p in (1, 2)), model.name)

    def test_every_item_reads_its_factory_value_and_read_only_items_refuse_writes(self):
        for bus in self.buses:
            with self.subTest(port=bus.name):
                wire = self.wire(bus)
                tables, problems = wire.read_tables()
                if problems:
                    self.fail("\n".join(problems))
                for servo in bus.servos:
                    problems += check_table(servo, tables[servo.id])
                problems += self.refused_writes(wire, tables)
                again, unread = wire.read_tables()
                if unread:
                    self.fail("\n".join(unread))
                for servo in bus.servos:
                    for item in servo.items:
                        before, after = item.decode(tables[servo.id]), item.decode(again[servo.id])
                        if before != after:
                            problems.append(f"{servo.label}: {item.key}({item.address}) read "
                                            f"{before}, then {after} after the refused writes")
                if problems:
                    self.fail(f"{len(problems)} problems:\n" + "\n".join(problems))

    def refused_writes(self, wire: Wire, tables: dict[int, bytes]) -> list[str]:
        """A Write of each read-only item of each servo; what was not refused as it must be."""
        problems = []
        error = ACCESS_ERROR_V2 if wire.bus.protocol == 2 else RANGE_ERROR_BIT_V1
        for servo in wire.bus.servos:
            for item in servo.items:
                if not item.read_only:
                    continue
                status = wire.write(servo, item, flipped(item.decode(tables[servo.id]), item))
                if not servo.model.answers_writes:
                    if status is not None:
                        problems.append(f"{servo.label}: Status Return Level 1 answered a "
                                        f"Write of {item.key}: {status}")
                elif status is None or (status.id, status.error, status.params) != (
                        servo.id, error, b""):
                    problems.append(f"{servo.label}: a Write of read-only {item.key}"
                                    f"({item.address}) answered {status}, not error "
                                    f"0x{error:02X}")
        return problems


if __name__ == "__main__":
    unittest.main()
