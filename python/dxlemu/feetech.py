"""FEETECH's FT-SCS protocol (SCS, STS, SMS and HLS serial bus servos) for a controller.

The frame is Protocol 1.0's (`packet1`, `frame_status1`: header FF FF, ID, LENGTH, instruction
or error, parameters, checksum ~sum), with FEETECH's own instruction set, one status error byte
of servo status bits, values 2 bytes at most in the series' byte order (SCS big-endian, STS, SMS
and HLS little-endian) and signed values in sign-magnitude. Written from FEETECH's protocol page
and memory tables (reference/feetech/), independently of the emulator's C++ codec.

`Client(port, protocol="feetech")` (dxlemu.protocol) speaks it; this module gives the codes and
the value conversions.
"""
from __future__ import annotations

from typing import Literal

PROTOCOL = "feetech"
"""The `protocol` argument of `Client` for a FEETECH bus."""

# Instruction codes (protocol-ft-scs.md "Instruction types"). 0x01 ~ 0x05 and 0x83 are
# DYNAMIXEL 1.0's codes with the same meaning; 0x06 and 0x08 are shared codes with other meanings.
PING, READ, WRITE, REG_WRITE, ACTION = 0x01, 0x02, 0x03, 0x04, 0x05
RECOVERY, RESTART, BACKUP, STATUS_RESET, POSITION_CALIBRATION = 0x06, 0x08, 0x09, 0x0A, 0x0B
SYNC_READ, SYNC_WRITE = 0x82, 0x83

# The status error byte: the servo status bits (memory tables, "Servo status", address 65).
ERROR_VOLTAGE = 0x01
ERROR_ANGLE_SENSOR = 0x02
ERROR_OVERHEAT = 0x04
ERROR_CURRENT = 0x08
ERROR_OVERLOAD = 0x20

ByteOrder = Literal["little", "big"]


def from_sign_magnitude(raw: int, sign_bit: int) -> int:
    """The value of a sign-magnitude item: bit `sign_bit` is the sign, the bits below it the
    magnitude (positions and speeds: bit 15; load and PWM: bit 10). Bits above the sign bit are
    not part of the value and must be 0."""
    magnitude = raw & ((1 << sign_bit) - 1)
    return -magnitude if raw & (1 << sign_bit) else magnitude


def to_sign_magnitude(value: int, sign_bit: int) -> int:
    """The raw number of `value` in sign-magnitude with sign bit `sign_bit` (0 without the sign
    bit). Raises ValueError when the magnitude does not fit below the sign bit."""
    if abs(value) >= 1 << sign_bit:
        raise ValueError(f"{value} does not fit a sign-magnitude value with sign bit {sign_bit}")
    return (abs(value) | (1 << sign_bit)) if value < 0 else value


def encode(value: int, size: int, *, order: ByteOrder = "little",
           sign_bit: int | None = None) -> bytes:
    """The `size` bytes of an item holding `value`, in the series' byte order, sign-magnitude
    when the item has a sign bit."""
    raw = to_sign_magnitude(value, sign_bit) if sign_bit is not None else value
    return raw.to_bytes(size, order)


def decode(data: bytes, *, order: ByteOrder = "little", sign_bit: int | None = None) -> int:
    """The value held by an item's bytes (a Read's data), as `encode` wrote it."""
    raw = int.from_bytes(data, order)
    return from_sign_magnitude(raw, sign_bit) if sign_bit is not None else raw
