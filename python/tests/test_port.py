"""Port over a pseudo-terminal pair of its own (no daemon): what it makes of the bytes a
servo's side writes."""
import os

import pytest

from dxlemu import BadPacket, Port, Status
from dxlemu.codec import packet2
from dxlemu.protocol import Client, CommTimeout

STATUS_1 = bytes.fromhex("ff ff fd 00 01 07 00 55 00 06 04 26 65 5d")


@pytest.fixture
def line():
    """(servo side fd, Port on the controller side)."""
    master, slave = os.openpty()
    port = Port(os.ttyname(slave))
    os.close(slave)
    yield master, port
    port.close()
    os.close(master)


def test_replies_written_together_are_read_one_at_a_time(line):
    servo, port = line
    os.write(servo, b"\x00\x00" + STATUS_1 + STATUS_1)
    assert port.status2(timeout=0.5) == Status(1, 0, bytes([6, 4, 38]))
    assert port.status2(timeout=0.5) == Status(1, 0, bytes([6, 4, 38]))
    assert port.status2(timeout=0.05) is None


def test_a_bad_crc_and_a_cut_packet_are_bad_packets(line):
    servo, port = line
    os.write(servo, STATUS_1[:-1] + b"\x00")
    with pytest.raises(BadPacket, match="bad CRC"):
        port.status2(timeout=0.5)
    os.write(servo, STATUS_1[:9])
    with pytest.raises(BadPacket, match="no whole status packet"):
        port.status2(timeout=0.05)
    os.write(servo, STATUS_1)
    assert port.status2(timeout=0.5).id == 1


def status(ident: int, error: int = 0, params: bytes = b"") -> bytes:
    """A 2.0 status packet: an instruction packet whose instruction is Status (0x55)."""
    return packet2(ident, 0x55, bytes([error]) + params)


def test_the_client_skips_replies_of_other_ids(line):
    servo, port = line
    client = Client(port, timeout=0.2)
    os.write(servo, status(2, 0, b"\x22") + status(1, 0x80, b"\x11"))
    assert client.receive(1) == (b"\x11", 0x80)


def test_the_client_sends_the_instruction_and_times_out_without_a_reply(line):
    servo, port = line
    client = Client(port, timeout=0.05)
    with pytest.raises(CommTimeout):
        client.read(3, 132, 4)
    assert os.read(servo, 64) == packet2(3, 0x02, bytes([132, 0, 4, 0]))
