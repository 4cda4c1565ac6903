"""Modbus RTU for a controller (a Modbus master): CRC-16/MODBUS, request frames, response
parsing with exception responses, and reading a response off the line by its expected length.

Written from the Modbus specifications as summarised in reference/modbus/modbus-rtu.md,
independently of the emulator's C++ codec, so that each checks the other. A frame is the server
address (1 byte), the function code (1), data (0 ~ 252 bytes, big-endian values) and the CRC
(2, low byte first). A DYNAMIXEL-P's control table is mapped onto holding registers: register R
holds the table's bytes 2R (its low byte) and 2R + 1 (its high byte), so a Modbus address is
40001 + floor(A / 2) for table address A (docs/modbus.md).

`Client(port, protocol="modbus")` (dxlemu.protocol) speaks it; this module gives the codes, the
frames and the register conversions.
"""
from __future__ import annotations

import time
from typing import Callable, Iterable, NamedTuple

from .codec import BadPacket, CommError

PROTOCOL = "modbus"
"""The `protocol` argument of `Client` for a Modbus RTU bus (and the protocol's spelling in the
emulator's configs, CLI and traces)."""

PROTOCOL_TYPE = 10
"""The Protocol Type item's value that makes a DYNAMIXEL-P speak Modbus RTU (2: Protocol 2.0)."""

BROADCAST_ADDRESS = 0
"""The address every server executes (writes only) and none answers."""
MIN_ADDRESS, MAX_ADDRESS = 1, 247
"""Unicast server addresses; 248 ~ 255 are reserved."""

REGISTER_BYTES = 2
"""Control-table bytes per register."""

MIN_FRAME, MAX_FRAME = 4, 256
"""A frame's size in bytes: address, function and CRC at least; 256 at most."""

# Function codes a register server offers (modbus-rtu.md "Function codes").
READ_HOLDING_REGISTERS = 0x03
READ_INPUT_REGISTERS = 0x04
WRITE_SINGLE_REGISTER = 0x06
DIAGNOSTICS = 0x08
WRITE_MULTIPLE_REGISTERS = 0x10
READ_WRITE_MULTIPLE_REGISTERS = 0x17
RETURN_QUERY_DATA = 0x0000
"""Diagnostics sub-function: the server echoes the request."""

FUNCTION_NAMES = {
    READ_HOLDING_REGISTERS: "Read Holding Registers",
    READ_INPUT_REGISTERS: "Read Input Registers",
    WRITE_SINGLE_REGISTER: "Write Single Register",
    DIAGNOSTICS: "Diagnostics",
    WRITE_MULTIPLE_REGISTERS: "Write Multiple Registers",
    READ_WRITE_MULTIPLE_REGISTERS: "Read/Write Multiple Registers",
}
"""The specification's name of each function code."""

EXCEPTION_FLAG = 0x80
"""Set in the function code of an exception response."""

# Exception codes (modbus-rtu.md "Exception responses").
ILLEGAL_FUNCTION = 0x01
ILLEGAL_DATA_ADDRESS = 0x02
ILLEGAL_DATA_VALUE = 0x03
SERVER_DEVICE_FAILURE = 0x04
SERVER_DEVICE_BUSY = 0x06

EXCEPTION_NAMES = {
    ILLEGAL_FUNCTION: "Illegal Function",
    ILLEGAL_DATA_ADDRESS: "Illegal Data Address",
    ILLEGAL_DATA_VALUE: "Illegal Data Value",
    SERVER_DEVICE_FAILURE: "Server Device Failure",
    SERVER_DEVICE_BUSY: "Server Device Busy",
}
"""The specification's name of each exception code."""

# Quantities a request may carry ("Function codes a register server offers").
MAX_READ_REGISTERS = 125
MAX_WRITE_REGISTERS = 123
MAX_READ_WRITE_WRITE_REGISTERS = 121

EXCEPTION_FRAME = 5
"""Size of an exception response: address, function | 0x80, exception code, CRC."""

# RTU timing ("RTU framing"): silence of 3.5 characters ends a frame, a gap over 1.5 characters
# breaks one; a character is 11 bits; above 19,200 bit/s both are fixed times.
CHAR_BITS = 11
SILENCE_TENTHS, GAP_TENTHS = 35, 15
FIXED_TIMING_ABOVE_BPS = 19200
FIXED_SILENCE_US, FIXED_GAP_US = 1750, 750


def silence_seconds(baud: int) -> float:
    """t3.5 at `baud` bit/s: the silence that ends a frame, which a master leaves before its
    next request on a real line."""
    if baud > FIXED_TIMING_ABOVE_BPS:
        return FIXED_SILENCE_US / 1e6
    return SILENCE_TENTHS * CHAR_BITS / (10 * baud)


def gap_seconds(baud: int) -> float:
    """t1.5 at `baud` bit/s: a longer gap inside a frame makes the receiver discard it."""
    if baud > FIXED_TIMING_ABOVE_BPS:
        return FIXED_GAP_US / 1e6
    return GAP_TENTHS * CHAR_BITS / (10 * baud)


def exception_name(code: int) -> str:
    """The name of exception code `code` ("Illegal Data Address"), or "exception 0xNN"."""
    return EXCEPTION_NAMES.get(code, f"exception 0x{code:02x}")


def function_name(code: int) -> str:
    """The name of function code `code` (without the exception flag), or "function 0xNN"."""
    return FUNCTION_NAMES.get(code & ~EXCEPTION_FLAG & 0xFF, f"function 0x{code:02x}")


class ModbusException(Exception):
    """A server's exception response: it refused the request with exception `code`.

    `name` is the code's name ("Illegal Data Address"), `function` the request's function code,
    `address` the server's."""

    def __init__(self, address: int, function: int, code: int):
        self.address = address
        self.function = function
        self.code = code
        self.name = exception_name(code)
        super().__init__(f"server {address} refused {function_name(function)} (0x{function:02x}): "
                         f"exception 0x{code:02x} {self.name}")


def crc16(data: bytes) -> int:
    """CRC-16/MODBUS: polynomial 0xA001 (0x8005 reflected), initial value 0xFFFF, no final XOR.
    Sent low byte first."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def frame(address: int, function: int, data: bytes = b"") -> bytes:
    """The RTU frame of `data` for function `function` of server `address`, CRC appended."""
    body = bytes([address, function]) + bytes(data)
    if len(body) + 2 > MAX_FRAME:
        raise ValueError(f"a Modbus frame holds at most {MAX_FRAME} bytes, not {len(body) + 2}")
    crc = crc16(body)
    return body + bytes([crc & 0xFF, crc >> 8])


class Frame(NamedTuple):
    """One frame taken apart: server address, function code (exception flag included) and the
    data between it and the CRC."""

    address: int
    function: int
    data: bytes


def split_frame(raw: bytes) -> Frame:
    """The parts of frame `raw`. Raises BadPacket when it is shorter than 4 bytes or its CRC
    does not match."""
    raw = bytes(raw)
    if len(raw) < MIN_FRAME:
        raise BadPacket("Modbus frame shorter than 4 bytes", raw, len(raw))
    if crc16(raw[:-2]) != raw[-2] | (raw[-1] << 8):
        raise BadPacket("bad CRC in Modbus frame", raw, len(raw))
    return Frame(raw[0], raw[1], raw[2:-2])


def _u16(value: int, what: str) -> bytes:
    if not 0 <= value <= 0xFFFF:
        raise ValueError(f"{what} must be 0 ~ 65535, got {value}")
    return value.to_bytes(2, "big")


def _register_value(value: int) -> int:
    """A register's 16 bits from `value`: 0 ~ 65535, or -32768 ~ -1 as two's complement."""
    if not -0x8000 <= value <= 0xFFFF:
        raise ValueError(f"a register holds -32768 ~ 65535, not {value}")
    return value & 0xFFFF


def _span(start: int, count: int, limit: int, what: str) -> bytes:
    if not 1 <= count <= limit:
        raise ValueError(f"{what} takes 1 ~ {limit} registers, not {count}")
    if start + count > 0x10000:
        raise ValueError(f"registers {start} ~ {start + count - 1} run past register 65535")
    return _u16(start, "the starting register") + count.to_bytes(2, "big")


def register_bytes(values: Iterable[int]) -> bytes:
    """Register values as on the wire: each big-endian (negative values as two's complement)."""
    return b"".join(_register_value(v).to_bytes(2, "big") for v in values)


def registers(data: bytes) -> list[int]:
    """The register values of wire bytes (big-endian words)."""
    if len(data) % 2:
        raise ValueError(f"registers take an even number of bytes, not {len(data)}")
    return [int.from_bytes(data[i:i + 2], "big") for i in range(0, len(data), 2)]


def table_bytes(values: Iterable[int]) -> bytes:
    """The control-table bytes that registers hold: each register's low byte (the even address)
    first, registers in order, so a 4-byte item reads as one little-endian number."""
    return b"".join(_register_value(v).to_bytes(2, "little") for v in values)


def table_registers(data: bytes) -> list[int]:
    """The register values holding control-table bytes `data` (from an even address)."""
    if len(data) % 2:
        raise ValueError(f"registers hold an even number of table bytes, not {len(data)}")
    return [int.from_bytes(data[i:i + 2], "little") for i in range(0, len(data), 2)]


def read_registers_request(address: int, start: int, count: int,
                           function: int = READ_HOLDING_REGISTERS) -> bytes:
    """Read Holding Registers (or Read Input Registers, function 0x04) of `count` registers
    from register `start` (PDU address: Modbus address 40001 is 0)."""
    if function not in (READ_HOLDING_REGISTERS, READ_INPUT_REGISTERS):
        raise ValueError(f"registers are read with function 0x03 or 0x04, not 0x{function:02x}")
    return frame(address, function, _span(start, count, MAX_READ_REGISTERS, "a read"))


def write_register_request(address: int, register: int, value: int) -> bytes:
    """Write Single Register: `value` into register `register`."""
    return frame(address, WRITE_SINGLE_REGISTER,
                 _u16(register, "the register") + register_bytes([value]))


def write_registers_request(address: int, start: int, values: Iterable[int]) -> bytes:
    """Write Multiple Registers: `values` into the registers from `start`."""
    data = register_bytes(values)
    span = _span(start, len(data) // 2, MAX_WRITE_REGISTERS, "a write")
    return frame(address, WRITE_MULTIPLE_REGISTERS, span + bytes([len(data)]) + data)


def read_write_registers_request(address: int, read_start: int, read_count: int,
                                 write_start: int, values: Iterable[int]) -> bytes:
    """Read/Write Multiple Registers: writes `values` from `write_start`, then reads
    `read_count` registers from `read_start` (the write is done first)."""
    data = register_bytes(values)
    read = _span(read_start, read_count, MAX_READ_REGISTERS, "the read of a read/write")
    write = _span(write_start, len(data) // 2, MAX_READ_WRITE_WRITE_REGISTERS,
                  "the write of a read/write")
    return frame(address, READ_WRITE_MULTIPLE_REGISTERS, read + write + bytes([len(data)]) + data)


def diagnostics_request(address: int, data: bytes = b"",
                        subfunction: int = RETURN_QUERY_DATA) -> bytes:
    """Diagnostics with `subfunction` (Return Query Data: the server echoes `data`)."""
    return frame(address, DIAGNOSTICS, _u16(subfunction, "the sub-function") + bytes(data))


def response_length(request: bytes) -> int | None:
    """The size of a normal response to request frame `request`, or None for a function this
    module does not know (its response has no length known in advance)."""
    function, data = request[1], request[2:-2]
    if function in (READ_HOLDING_REGISTERS, READ_INPUT_REGISTERS) and len(data) >= 4:
        return 5 + 2 * int.from_bytes(data[2:4], "big")
    if function == READ_WRITE_MULTIPLE_REGISTERS and len(data) >= 4:
        return 5 + 2 * int.from_bytes(data[2:4], "big")
    if function in (WRITE_SINGLE_REGISTER, WRITE_MULTIPLE_REGISTERS):
        return 8
    if function == DIAGNOSTICS:
        return len(request)  # an echo
    return None


def parse_response(request: bytes, response: bytes) -> Frame:
    """Checks `response` against the request frame `request` and returns it taken apart.

    Raises ModbusException for an exception response, and BadPacket for a bad CRC, another
    server's or function's frame, a wrong size or byte count, or a write or diagnostics echo
    that does not echo the request."""
    asked = split_frame(request)
    got = split_frame(response)
    if got.address != asked.address:
        raise BadPacket(f"response from server {got.address} to a request for server "
                        f"{asked.address}", response, len(response))
    if got.function == asked.function | EXCEPTION_FLAG:
        if len(got.data) != 1:
            raise BadPacket("exception response without exactly one exception code", response,
                            len(response))
        raise ModbusException(got.address, asked.function, got.data[0])
    if got.function != asked.function:
        raise BadPacket(f"response of function 0x{got.function:02x} to function "
                        f"0x{asked.function:02x}", response, len(response))
    expected = response_length(request)
    if expected is not None and len(response) != expected:
        raise BadPacket(f"{function_name(asked.function)} response of {len(response)} bytes, "
                        f"expected {expected}", response, len(response))
    if asked.function in (READ_HOLDING_REGISTERS, READ_INPUT_REGISTERS,
                          READ_WRITE_MULTIPLE_REGISTERS):
        if not got.data or got.data[0] != len(got.data) - 1:
            raise BadPacket("byte count does not match the registers read", response,
                            len(response))
    elif asked.function in (WRITE_SINGLE_REGISTER, DIAGNOSTICS):
        if got.data != asked.data:
            raise BadPacket(f"{function_name(asked.function)} response is not the request's echo",
                            response, len(response))
    elif asked.function == WRITE_MULTIPLE_REGISTERS and got.data != asked.data[:4]:
        raise BadPacket("Write Multiple Registers response names other registers", response,
                        len(response))
    return got


Reader = Callable[[int, float], bytes]
"""`read(count, timeout)`: up to `count` bytes within `timeout` seconds (Port.read)."""


def read_response(read: Reader, request: bytes, timeout: float) -> bytes | None:
    """Reads the response to `request` with `read`, by its expected size: the exception size
    when the function byte has the exception flag, else the normal response's size
    (response_length). Returns the frame's bytes, unchecked (parse_response checks them), or
    None when nothing at all arrived within `timeout` seconds. Raises BadPacket for a response
    cut short, and CommError for a function whose response size is unknown."""
    expected = response_length(request)
    deadline = time.monotonic() + timeout
    got = read(2, timeout)
    if not got:
        return None
    if len(got) == 2:
        if got[1] & EXCEPTION_FLAG:
            expected = EXCEPTION_FRAME
        elif expected is None:
            raise CommError(f"no response size known for function 0x{request[1]:02x}")
        got += read(expected - 2, max(0.0, deadline - time.monotonic()))
    if len(got) < (expected or EXCEPTION_FRAME):
        raise BadPacket("Modbus response cut short before the timeout", got, len(got))
    return got
