"""Packets as bytes: vectors from the ROBOTIS protocol pages, framing with garbage and errors."""
import random

import pytest

from dxlemu.codec import (BadPacket, Status, crc16, frame_status1, frame_status2, packet1,
                          packet2, stuff, unstuff)

PING_1 = bytes.fromhex("ff ff fd 00 01 03 00 01 19 4e")  # protocol2.md, Ping example
PING_1_STATUS = bytes.fromhex("ff ff fd 00 01 07 00 55 00 06 04 26 65 5d")  # XM model 1030, fw 38


def test_ping_packet_and_crc_match_the_protocol_page():
    assert packet2(1, 0x01) == PING_1
    assert crc16(PING_1[:-2]) == 0x4E19


def test_protocol_1_packet_has_the_inverted_sum_checksum():
    assert packet1(1, 0x02, bytes([0x2B, 0x01])) == bytes.fromhex("ff ff 01 04 02 2b 01 cc")


def test_stuffing_round_trips_and_inserts_fd_after_the_header_pattern():
    assert stuff(b"\xff\xff\xfd\x01") == b"\xff\xff\xfd\xfd\x01"
    rng = random.Random(7)
    for _ in range(2000):
        region = bytes(rng.choice((0xFF, 0xFD, 0x00)) for _ in range(rng.randint(0, 12)))
        assert unstuff(stuff(region)) == region


def test_a_status_is_found_after_garbage_and_split_reads():
    buffer = b"\x00\x12\xff" + PING_1_STATUS + b"\xff\xff"
    status, used = frame_status2(buffer)
    assert status == Status(1, 0, bytes([0x06, 0x04, 0x26]))
    assert buffer[used:] == b"\xff\xff"
    assert frame_status2(PING_1_STATUS[:9]) == (None, 0)


def test_an_echoed_instruction_is_skipped():
    status, used = frame_status2(PING_1 + PING_1_STATUS)
    assert status.id == 1 and used == len(PING_1) + len(PING_1_STATUS)


def test_a_bad_crc_raises_with_the_bytes_to_drop():
    corrupt = PING_1_STATUS[:-1] + b"\x00"
    with pytest.raises(BadPacket) as error:
        frame_status2(b"\x01" + corrupt)
    assert error.value.consumed == 1 + len(corrupt)
    assert error.value.data == corrupt


def test_protocol_1_status_is_framed_and_checked():
    reply = bytes.fromhex("ff ff 01 02 00 fc")
    assert frame_status1(b"\xff" + reply) == (Status(1, 0, b""), len(reply) + 1)
    with pytest.raises(BadPacket):
        frame_status1(reply[:-1] + b"\x00")
