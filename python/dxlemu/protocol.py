"""A minimal servo controller over a serial port: Ping, Read, Write, Reboot, Sync Read and Sync
Write in DYNAMIXEL Protocol 2.0, Protocol 1.0 (all but Sync Read) or FEETECH's FT-SCS protocol
(`protocol="feetech"`, dxlemu.feetech), each returning the reply's data and error byte, or
raising CommError when no valid reply came in time. Over Modbus RTU (`protocol="modbus"`,
dxlemu.modbus) Ping, Read and Write map onto holding registers, beside register-level methods,
and a refusal raises ModbusException.

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
from . import modbus
from .feetech import PROTOCOL as FEETECH
from .modbus import PROTOCOL as MODBUS
from .modbus import ModbusException
from .port import BAUD_RATES, Port

__all__ = [
    "ACTION", "ALERT", "BAUD_RATES", "BROADCAST_ID", "BULK_READ", "BULK_WRITE", "CLEAR",
    "FACTORY_RESET", "PING", "READ", "REBOOT", "REG_WRITE", "STATUS", "SYNC_READ", "SYNC_WRITE",
    "WRITE", "BadPacket", "Client", "CommError", "CommTimeout", "FEETECH", "MODBUS",
    "ModbusException", "Port", "Reply", "Status",
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
    of Reboot; Modbus RTU with `protocol="modbus"`: see the Modbus methods below).

    Every exchange discards stale input, sends one instruction and waits up to `timeout`
    seconds for the addressed servo's status; status packets of other IDs are skipped. A
    timeout raises CommTimeout, a bad CRC or checksum BadPacket (both CommError). Usable as a
    context manager; a port given by path is opened here and closed by `close`."""

    def __init__(self, port: Port | str, *, baud: int = 57600, protocol: int | str = 2,
                 timeout: float = 0.5):
        if protocol not in (1, 2, FEETECH, MODBUS):
            raise ValueError(f"protocol must be 1, 2, {FEETECH!r} or {MODBUS!r}, "
                             f"got {protocol!r}")
        self._owns_port = not isinstance(port, Port)
        self.port = Port(port, baud) if isinstance(port, str) else port
        self.protocol = protocol
        self.timeout = timeout

    def packet(self, ident: int, instruction: int, params: bytes = b"") -> bytes:
        """The instruction packet in this client's protocol (Modbus: the frame of function
        `instruction` with data `params` for server `ident`)."""
        if self.protocol == MODBUS:
            return modbus.frame(ident, instruction, params)
        build = packet2 if self.protocol == 2 else packet1
        return build(ident, instruction, params)

    def send(self, ident: int, instruction: int, params: bytes = b"") -> None:
        """Sends an instruction without waiting for a reply (broadcasts, Status Return Level 0)."""
        self.port.flush_input()
        self.port.write(self.packet(ident, instruction, params))

    def receive(self, ident: int, timeout: float | None = None) -> Reply:
        """The next status packet of servo `ident`, skipping other IDs' packets. Not over
        Modbus, whose responses are read by the request they answer (`transact`)."""
        if self.protocol == MODBUS:
            raise CommError("a Modbus response is read with its request: use transact")
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        framed = self.port.status2 if self.protocol == 2 else self.port.status1
        while True:
            status = framed(max(0.0, deadline - time.monotonic()))
            if status is None:
                raise CommTimeout(f"no reply from servo {ident}")
            if status.id == ident:
                return Reply(status.params, status.error)

    def transact(self, ident: int, instruction: int, params: bytes = b"") -> Reply:
        """Sends one instruction to servo `ident` and returns its reply. Modbus: the response
        to function `instruction` with data `params`, its data (after the function code) as
        `data` and 0 as `error`; an exception response raises ModbusException."""
        if self.protocol == MODBUS:
            response = self._modbus(self.packet(ident, instruction, params))
            return Reply(response.data if response else b"", 0)
        self.send(ident, instruction, params)
        return self.receive(ident)

    def _address(self, address: int) -> bytes:
        return address.to_bytes(2 if self.protocol == 2 else 1, "little")

    def ping(self, ident: int) -> Reply:
        """Ping. In 2.0 `data` is the model number (2 bytes) and the firmware version. Modbus
        has no Ping: a read of register 0, the Model Number, whose 2 bytes are `data`."""
        if self.protocol == MODBUS:
            return self.read(ident, 0, 2)
        return self.transact(ident, PING)

    def read(self, ident: int, address: int, length: int) -> Reply:
        """Read of `length` bytes from `address` of the control table. Modbus: Read Holding
        Registers of registers address/2 ~ (address+length)/2 - 1; `data` is the table's bytes
        (each register's low byte first); odd addresses and lengths raise ValueError."""
        if self.protocol == MODBUS:
            start, count = self._registers(address, length)
            return Reply(modbus.table_bytes(self.read_registers(ident, start, count)), 0)
        return self.transact(ident, READ, self._address(address) + self._address(length))

    def write(self, ident: int, address: int, data: bytes) -> Reply | None:
        """Write of `data` at `address`. Modbus: Write Single Register for one register, else
        Write Multiple Registers, of the registers holding those table bytes (odd addresses and
        lengths raise ValueError); a broadcast (server 0) waits for no reply and returns None."""
        if self.protocol == MODBUS:
            start, _ = self._registers(address, len(data))
            values = modbus.table_registers(bytes(data))
            if len(values) == 1:
                self.write_register(ident, start, values[0])
            else:
                self.write_registers(ident, start, values)
            return None if ident == modbus.BROADCAST_ADDRESS else Reply(b"", 0)
        return self.transact(ident, WRITE, self._address(address) + bytes(data))

    def write_int(self, ident: int, address: int, value: int, size: int) -> Reply | None:
        """Write of `value` as a little-endian number of `size` bytes (negative: two's
        complement)."""
        return self.write(ident, address, value.to_bytes(size, "little", signed=value < 0))

    def reboot(self, ident: int) -> Reply | None:
        """Reboot: the servo answers, then restarts and is silent for its boot time. FEETECH's
        Restart (the same code) sends no status: None, without waiting."""
        if self.protocol == FEETECH:
            self.send(ident, REBOOT)
            return None
        self._not_modbus("Reboot")
        return self.transact(ident, REBOOT)

    def sync_read(self, address: int, length: int, ids: Iterable[int]) -> dict[int, Reply]:
        """Sync Read (Protocol 2.0 and FEETECH) of `length` bytes at `address` from each of
        `ids`, replies in that order. A servo that does not answer raises CommTimeout (the ones
        after it wait for it in vain on a real bus)."""
        if self.protocol == 1:
            raise CommError("Sync Read is not a Protocol 1.0 instruction")
        self._not_modbus("Sync Read")
        ids = list(ids)
        self.send(BROADCAST_ID, SYNC_READ,
                  self._address(address) + self._address(length) + bytes(ids))
        return {ident: self.receive(ident) for ident in ids}

    def sync_write(self, address: int, data: Mapping[int, bytes]) -> None:
        """Sync Write of each servo's bytes in `data` (ID to bytes, all of one length) at
        `address`. Nobody answers it."""
        self._not_modbus("Sync Write")
        blocks = [bytes(block) for block in data.values()]
        length = len(blocks[0]) if blocks else 0
        if any(len(block) != length for block in blocks):
            raise ValueError("Sync Write needs the same number of bytes for every servo")
        params = self._address(address) + self._address(length)
        for ident, block in zip(data, blocks):
            params += bytes([ident]) + block
        self.send(BROADCAST_ID, SYNC_WRITE, params)

    # Modbus RTU (protocol="modbus"): registers of two control-table bytes, register R holding
    # bytes 2R (low) and 2R + 1 (high); values are unsigned 16-bit numbers (writes also take
    # -32768 ~ -1). Every call sends one request and reads its response by its expected size;
    # an exception response raises ModbusException, no response CommTimeout, a bad CRC or a
    # response that does not fit the request BadPacket. Broadcast (server 0) writes wait for no
    # response; broadcast reads raise ValueError (nobody would answer).

    def read_registers(self, ident: int, start: int, count: int,
                       function: int = modbus.READ_HOLDING_REGISTERS) -> list[int]:
        """Read Holding Registers (function 3) or Read Input Registers (4): `count` register
        values from register `start` (PDU address; Modbus address 40001 + start)."""
        self._only_modbus("read_registers")
        self._unicast(ident, "a read")
        response = self._modbus(modbus.read_registers_request(ident, start, count, function))
        assert response is not None
        return modbus.registers(response.data[1:])

    def write_register(self, ident: int, register: int, value: int) -> None:
        """Write Single Register: `value` into register `register`."""
        self._only_modbus("write_register")
        self._modbus(modbus.write_register_request(ident, register, value))

    def write_registers(self, ident: int, start: int, values: Iterable[int]) -> None:
        """Write Multiple Registers: `values` into the registers from `start`."""
        self._only_modbus("write_registers")
        self._modbus(modbus.write_registers_request(ident, start, values))

    def read_write_registers(self, ident: int, read_start: int, read_count: int,
                             write_start: int, values: Iterable[int]) -> list[int]:
        """Read/Write Multiple Registers: writes `values` from `write_start`, then returns
        `read_count` register values from `read_start`."""
        self._only_modbus("read_write_registers")
        self._unicast(ident, "a read/write")
        response = self._modbus(modbus.read_write_registers_request(
            ident, read_start, read_count, write_start, values))
        assert response is not None
        return modbus.registers(response.data[1:])

    def diagnostics_echo(self, ident: int, data: bytes = b"") -> bytes:
        """Diagnostics, Return Query Data: the bytes the server echoed (`data` when it
        behaves)."""
        self._only_modbus("diagnostics_echo")
        self._unicast(ident, "a diagnostics request")
        response = self._modbus(modbus.diagnostics_request(ident, data))
        assert response is not None
        return response.data[2:]

    def _modbus(self, request: bytes) -> modbus.Frame | None:
        """Sends request frame `request` and returns its response checked against it; None for
        a broadcast."""
        self.port.flush_input()
        self.port.write(request)
        if request[0] == modbus.BROADCAST_ADDRESS:
            return None
        response = modbus.read_response(self.port.read, request, self.timeout)
        if response is None:
            raise CommTimeout(f"no response from server {request[0]}")
        return modbus.parse_response(request, response)

    def _registers(self, address: int, length: int) -> tuple[int, int]:
        """The registers holding `length` table bytes from `address`: (start, count)."""
        if address % modbus.REGISTER_BYTES or length % modbus.REGISTER_BYTES or length <= 0:
            raise ValueError(f"Modbus reaches whole registers: an even address and a positive "
                             f"even length, not address {address} length {length}")
        return address // modbus.REGISTER_BYTES, length // modbus.REGISTER_BYTES

    def _only_modbus(self, method: str) -> None:
        if self.protocol != MODBUS:
            raise CommError(f"{method} is a Modbus method; this client speaks {self.protocol!r}")

    def _not_modbus(self, instruction: str) -> None:
        if self.protocol == MODBUS:
            raise CommError(f"{instruction} has no Modbus function")

    @staticmethod
    def _unicast(ident: int, what: str) -> None:
        if ident == modbus.BROADCAST_ADDRESS:
            raise ValueError(f"{what} cannot be broadcast: no server would answer it")

    def close(self) -> None:
        """Closes the port when this client opened it."""
        if self._owns_port:
            self.port.close()

    def __enter__(self) -> Client:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
