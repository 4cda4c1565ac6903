"""DYNAMIXEL packets as bytes, both ways, for a controller: no I/O, no clock.

Instruction packets are built and status packets found in a byte buffer (after any garbage),
for Protocol 1.0 and 2.0. Written from the ROBOTIS protocol pages (protocol1.md, protocol2.md,
protocol2-crc.md), independently of the emulator's C++ codec, so that each checks the other.
"""
from __future__ import annotations

from typing import NamedTuple

BROADCAST_ID = 0xFE
"""The ID every servo hears."""

# Instruction codes (protocol2.md "Instruction"; 1.0 uses the same values).
PING, READ, WRITE, REG_WRITE, ACTION = 0x01, 0x02, 0x03, 0x04, 0x05
FACTORY_RESET, REBOOT, CLEAR, STATUS = 0x06, 0x08, 0x10, 0x55
SYNC_READ, SYNC_WRITE, BULK_READ, BULK_WRITE = 0x82, 0x83, 0x92, 0x93

ALERT = 0x80
"""Protocol 2.0 error byte: a hardware error is latched (Hardware Error Status is not 0)."""

HEADER2 = b"\xff\xff\xfd\x00"
HEADER1 = b"\xff\xff"
_MIN_LENGTH2 = 3  # instruction, CRC (2); a status adds its error byte
_MIN_STATUS_LENGTH2 = 4
_MIN_LENGTH1 = 2  # error, checksum


class Status(NamedTuple):
    """One status packet: the servo's ID, its error byte and its parameters (unstuffed)."""

    id: int
    error: int
    params: bytes


class CommError(Exception):
    """A failed exchange with a servo: no reply in time, or a reply that is not a valid packet."""


class BadPacket(CommError):
    """Bytes that should have been a status packet and are not (bad CRC or checksum, impossible
    length, or garbage only). `data` holds the bytes in question."""

    def __init__(self, message: str, data: bytes = b"", consumed: int = 0):
        super().__init__(f"{message}: {data.hex(' ')}" if data else message)
        self.data = bytes(data)
        self.consumed = consumed
        """How many bytes of the buffer being framed the bad packet and the garbage before it
        took: the framer's caller drops them."""


def crc16(data: bytes) -> int:
    """CRC-16 of Protocol 2.0: polynomial 0x8005, initial value 0, MSB first (protocol2-crc.md)."""
    crc = 0
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def checksum1(body: bytes) -> int:
    """Protocol 1.0 checksum of ID, LENGTH, INSTRUCTION/ERROR and parameters."""
    return ~sum(body) & 0xFF


def stuff(region: bytes) -> bytes:
    """Inserts 0xFD after every FF FF FD (protocol2.md "Packet Process")."""
    out = bytearray()
    for byte in region:
        out.append(byte)
        if len(out) >= 3 and out[-3:] == b"\xff\xff\xfd":
            out.append(0xFD)
    return bytes(out)


def unstuff(region: bytes) -> bytes:
    """Removes the 0xFD that follows every FF FF FD: the inverse of `stuff`."""
    out = bytearray()
    index = 0
    while index < len(region):
        out.append(region[index])
        stuffed = out[-3:] == b"\xff\xff\xfd" and region[index + 1:index + 2] == b"\xfd"
        index += 2 if stuffed else 1  # past the stuffed 0xFD too
    return bytes(out)


def packet2(ident: int, instruction: int, params: bytes = b"") -> bytes:
    """A Protocol 2.0 instruction packet: header, ID, length, stuffed instruction and
    parameters, CRC."""
    body = stuff(bytes([instruction]) + params)
    length = len(body) + 2
    head = HEADER2 + bytes([ident, length & 0xFF, length >> 8]) + body
    crc = crc16(head)
    return head + bytes([crc & 0xFF, crc >> 8])


def packet1(ident: int, instruction: int, params: bytes = b"") -> bytes:
    """A Protocol 1.0 instruction packet."""
    body = bytes([ident, len(params) + 2, instruction]) + params
    return HEADER1 + body + bytes([checksum1(body)])


def _keep_header_prefix(buffer: bytes, header: bytes) -> int:
    """How many bytes at the start of `buffer` (which holds no whole header) cannot begin a
    header: the bytes to drop while waiting for more."""
    for keep in range(min(len(header) - 1, len(buffer)), 0, -1):
        if buffer[-keep:] == header[:keep]:
            return len(buffer) - keep
    return len(buffer)


def _whole_packet(buffer: bytes, index: int, head: int, length_bytes: int,
                  min_length: int) -> int | None:
    """The LENGTH of the packet that starts at `index` (its LENGTH field, little-endian, is the
    last `length_bytes` of its first `head` bytes), or None until all of it is in `buffer`.
    Raises BadPacket for a LENGTH below `min_length`."""
    if len(buffer) < index + head:
        return None
    length = int.from_bytes(buffer[index + head - length_bytes:index + head], "little")
    if length < min_length:
        raise BadPacket(f"impossible status length {length}", buffer[index:index + head],
                        consumed=index + head)
    return length if len(buffer) >= index + head + length else None


def frame_status2(buffer: bytes) -> tuple[Status | None, int]:
    """Looks for one Protocol 2.0 status packet in `buffer`, skipping garbage before it.

    Returns (status, bytes consumed) when a whole packet is there, else (None, bytes that can
    be dropped as garbage) and more bytes are needed. Instruction packets (an echo of the
    controller's own) are consumed and skipped. Raises BadPacket for a bad CRC or impossible
    length; its `consumed` says how many bytes to drop."""
    start = 0
    while True:
        index = buffer.find(HEADER2, start)
        if index < 0:
            return None, start + _keep_header_prefix(buffer[start:], HEADER2)
        length = _whole_packet(buffer, index, 7, 2, _MIN_LENGTH2)
        if length is None:
            return None, index
        end = index + 7 + length
        packet = bytes(buffer[index:end])
        if crc16(packet[:-2]) != (packet[-2] | (packet[-1] << 8)):
            raise BadPacket("bad CRC in status packet", packet, consumed=end)
        if packet[7] != STATUS:
            start = end  # an instruction packet, not a reply: skip it
            continue
        if length < _MIN_STATUS_LENGTH2:
            raise BadPacket("status packet without an error byte", packet, consumed=end)
        return Status(packet[4], packet[8], unstuff(packet[9:-2])), end


def frame_status1(buffer: bytes) -> tuple[Status | None, int]:
    """Looks for one Protocol 1.0 status packet in `buffer`, as `frame_status2` does (a 1.0
    packet has no instruction/status marker: whatever parses is taken as a status)."""
    index = buffer.find(HEADER1)
    while index >= 0 and index + 2 < len(buffer) and buffer[index + 2] == 0xFF:
        index += 1  # FF FF FF: the header starts one byte later
    if index < 0:
        return None, _keep_header_prefix(buffer, HEADER1)
    length = _whole_packet(buffer, index, 4, 1, _MIN_LENGTH1)
    if length is None:
        return None, index
    end = index + 4 + length
    packet = bytes(buffer[index:end])
    if checksum1(packet[2:-1]) != packet[-1]:
        raise BadPacket("bad checksum in status packet", packet, consumed=end)
    return Status(packet[2], packet[4], packet[5:-1]), end

