"""A minimal servo controller over a serial port: Ping, Read, Write, Reboot, Sync Read and Sync
Write in DYNAMIXEL Protocol 2.0, Protocol 1.0 (all but Sync Read) or FEETECH's FT-SCS protocol
(`protocol="feetech"`, dxlemu.feetech), each returning the reply's data and error byte, or
raising CommError when no valid reply came in time.

The packet codec (`crc16`, `stuff`, `packet2`, ...) and `Port` are re-exported from here, so
`from dxlemu.protocol import ...` gives a controller everything it needs.
"""
from __future__ import annotations

import time
from typing import Iterable, Mapping, NamedTuple

from .codec import (ACTION, ALERT, BROADCAST_ID, BULK_READ, BULK_WRITE, CLEAR, FACTORY_RESET, PING,
                    READ, REBOOT, REG_WRITE, STATUS, SYNC_READ, SYNC_WRITE, WRITE, BadPacket,
                    CommError, Status, checksum1, crc16, frame_status1, frame_status2, packet1,
                    packet2, stuff, unstuff)
from .feetech import PROTOCOL as FEETECH
from .port import BAUD_RATES, Port

__all__ = [
    "ACTION", "ALERT", "BAUD_RATES", "BROADCAST_ID", "BULK_READ", "BULK_WRITE", "CLEAR",
    "FACTORY_RESET", "PING", "READ", "REBOOT", "REG_WRITE", "STATUS", "SYNC_READ", "SYNC_WRITE",
    "WRITE", "BadPacket", "Client", "CommError", "CommTimeout", "FEETECH", "Port", "Reply",
    "Status",
    "checksum1", "crc16", "frame_status1", "frame_status2", "packet1", "packet2", "stuff",
    "unstuff",
]


class CommTimeout(CommError):
    """No reply (or only replies of other IDs) within the timeout."""


class Reply(NamedTuple):
    """What a servo answered: the parameters of its status packet and its error byte."""

    data: bytes
    error: int

    @property
    def alert(self) -> bool:
        """Protocol 2.0: the alert bit, set while a hardware error is latched."""
        return bool(self.error & ALERT)

    @property
    def value(self) -> int:
        """`data` as an unsigned little-endian number (a Read of one item)."""
        return int.from_bytes(self.data, "little")

    @property
    def signed(self) -> int:
        """`data` as a signed little-endian number (Present Position, Present Current...)."""
        return int.from_bytes(self.data, "little", signed=True)


class Client:
    """A controller on one serial port, speaking Protocol 2.0 (or 1.0 with `protocol=1`, FEETECH
    with `protocol="feetech"`: 1.0's frame, one-byte addresses, Sync Read, and Restart in place
    of Reboot).

    Every exchange discards stale input, sends one instruction and waits up to `timeout`
    seconds for the addressed servo's status; status packets of other IDs are skipped. A
    timeout raises CommTimeout, a bad CRC or checksum BadPacket (both CommError). Usable as a
    context manager; a port given by path is opened here and closed by `close`."""

    def __init__(self, port: Port | str, *, baud: int = 57600, protocol: int | str = 2,
                 timeout: float = 0.5):
        if protocol not in (1, 2, FEETECH):
            raise ValueError(f"protocol must be 1, 2 or {FEETECH!r}, got {protocol!r}")
        self._owns_port = not isinstance(port, Port)
        self.port = Port(port, baud) if isinstance(port, str) else port
        self.protocol = protocol
        self.timeout = timeout

    def packet(self, ident: int, instruction: int, params: bytes = b"") -> bytes:
        """The instruction packet in this client's protocol."""
        build = packet2 if self.protocol == 2 else packet1
        return build(ident, instruction, params)

    def send(self, ident: int, instruction: int, params: bytes = b"") -> None:
        """Sends an instruction without waiting for a reply (broadcasts, Status Return Level 0)."""
        self.port.flush_input()
        self.port.write(self.packet(ident, instruction, params))

    def receive(self, ident: int, timeout: float | None = None) -> Reply:
        """The next status packet of servo `ident`, skipping other IDs' packets."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        framed = self.port.status2 if self.protocol == 2 else self.port.status1
        while True:
            status = framed(max(0.0, deadline - time.monotonic()))
            if status is None:
                raise CommTimeout(f"no reply from servo {ident}")
            if status.id == ident:
                return Reply(status.params, status.error)

    def transact(self, ident: int, instruction: int, params: bytes = b"") -> Reply:
        """Sends one instruction to servo `ident` and returns its reply."""
        self.send(ident, instruction, params)
        return self.receive(ident)

    def _address(self, address: int) -> bytes:
        return address.to_bytes(2 if self.protocol == 2 else 1, "little")

    def ping(self, ident: int) -> Reply:
        """Ping. In 2.0 `data` is the model number (2 bytes) and the firmware version."""
        return self.transact(ident, PING)

    def read(self, ident: int, address: int, length: int) -> Reply:
        """Read of `length` bytes from `address` of the control table."""
        return self.transact(ident, READ, self._address(address) + self._address(length))

    def write(self, ident: int, address: int, data: bytes) -> Reply:
        """Write of `data` at `address`."""
        return self.transact(ident, WRITE, self._address(address) + bytes(data))

    def write_int(self, ident: int, address: int, value: int, size: int) -> Reply:
        """Write of `value` as a little-endian number of `size` bytes (negative: two's
        complement)."""
        return self.write(ident, address, value.to_bytes(size, "little", signed=value < 0))

    def reboot(self, ident: int) -> Reply | None:
        """Reboot: the servo answers, then restarts and is silent for its boot time. FEETECH's
        Restart (the same code) sends no status: None, without waiting."""
        if self.protocol == FEETECH:
            self.send(ident, REBOOT)
            return None
        return self.transact(ident, REBOOT)

    def sync_read(self, address: int, length: int, ids: Iterable[int]) -> dict[int, Reply]:
        """Sync Read (Protocol 2.0 and FEETECH) of `length` bytes at `address` from each of
        `ids`, replies in that order. A servo that does not answer raises CommTimeout (the ones
        after it wait for it in vain on a real bus)."""
        if self.protocol == 1:
            raise CommError("Sync Read is not a Protocol 1.0 instruction")
        ids = list(ids)
        self.send(BROADCAST_ID, SYNC_READ,
                  self._address(address) + self._address(length) + bytes(ids))
        return {ident: self.receive(ident) for ident in ids}

    def sync_write(self, address: int, data: Mapping[int, bytes]) -> None:
        """Sync Write of each servo's bytes in `data` (ID to bytes, all of one length) at
        `address`. Nobody answers it."""
        blocks = [bytes(block) for block in data.values()]
        length = len(blocks[0]) if blocks else 0
        if any(len(block) != length for block in blocks):
            raise ValueError("Sync Write needs the same number of bytes for every servo")
        params = self._address(address) + self._address(length)
        for ident, block in zip(data, blocks):
            params += bytes([ident]) + block
        self.send(BROADCAST_ID, SYNC_WRITE, params)

    def close(self) -> None:
        """Closes the port when this client opened it."""
        if self._owns_port:
            self.port.close()

    def __enter__(self) -> Client:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
