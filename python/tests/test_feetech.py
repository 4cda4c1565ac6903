"""FEETECH's FT-SCS protocol in the package: the example frames of FEETECH's protocol page
(reference/feetech/protocol-ft-scs.md), the client's FEETECH instructions on a recorded port,
and sign-magnitude values."""
import pytest

from dxlemu import feetech
from dxlemu.codec import Status, frame_status1, packet1
from dxlemu.protocol import Client, CommError, FEETECH


def frame(text: str) -> bytes:
    return bytes.fromhex(text)


class RecordedPort:
    """A port whose replies are canned bytes: records what the client writes and frames the
    replies as the real Port does."""

    def __init__(self, replies: bytes = b""):
        self.written = bytearray()
        self.pending = bytes(replies)

    def flush_input(self) -> None:
        pass

    def write(self, data: bytes) -> None:
        self.written += data

    def status1(self, timeout: float = 1.0) -> Status | None:
        status, used = frame_status1(self.pending)
        self.pending = self.pending[used:]
        return status


def test_ping_read_and_write_frames_match_the_protocol_page():
    # 4.1 PING, 4.2 READ (2 bytes from 0x38), 4.3 WRITE (ID to 5, broadcast), 4.3 WRITE (goal).
    assert packet1(1, feetech.PING) == frame("ff ff 01 02 01 fb")
    assert packet1(1, feetech.READ, bytes([0x38, 0x02])) == frame("ff ff 01 04 02 38 02 be")
    assert packet1(0xFE, feetech.WRITE, bytes([0x05, 0x01])) == frame("ff ff fe 04 03 05 01 f4")
    assert packet1(1, feetech.WRITE, frame("2a 00 08 00 00 e8 03")) == frame(
        "ff ff 01 09 03 2a 00 08 00 00 e8 03 d5")
    assert packet1(0xFE, feetech.ACTION) == frame("ff ff fe 02 05 fa")
    assert packet1(1, feetech.STATUS_RESET) == frame("ff ff 01 02 0a f2")
    assert packet1(1, feetech.POSITION_CALIBRATION, bytes([0x00, 0x04])) == frame(
        "ff ff 01 04 0b 00 04 eb")


def test_status_frames_of_the_protocol_page_parse():
    status, used = frame_status1(frame("ff ff 01 04 00 18 05 dd"))
    assert status == Status(1, 0, bytes([0x18, 0x05])) and used == 8
    assert feetech.decode(status.params) == 0x0518  # STS: low byte first


def test_the_client_speaks_feetech_one_byte_addresses():
    port = RecordedPort(frame("ff ff 01 04 00 18 05 dd"))
    client = Client(port, protocol=FEETECH)
    reply = client.read(1, 0x38, 2)
    assert bytes(port.written) == frame("ff ff 01 04 02 38 02 be")
    assert reply.data == bytes([0x18, 0x05]) and reply.error == 0


def test_sync_write_and_sync_read_frames_match_the_protocol_page():
    # 4.6 SYNC WRITE: goal 0x0800, time 0, speed 1000 to IDs 1 ~ 4.
    port = RecordedPort()
    client = Client(port, protocol=FEETECH)
    block = frame("00 08 00 00 e8 03")
    client.sync_write(0x2A, {1: block, 2: block, 3: block, 4: block})
    assert bytes(port.written) == frame(
        "ff ff fe 20 83 2a 06 01 00 08 00 00 e8 03 02 00 08 00 00 e8 03 03 00 08 00 00 e8 03"
        " 04 00 08 00 00 e8 03 58")
    # 4.7 SYNC READ: 8 bytes from 0x38 of IDs 1 and 2, one status each, in request order.
    port = RecordedPort(frame("ff ff 01 0a 00 00 08 00 00 00 00 79 1e 55"
                              "ff ff 02 0a 00 ff 07 00 00 00 00 77 23 53"))
    client = Client(port, protocol=FEETECH)
    replies = client.sync_read(0x38, 8, [1, 2])
    assert bytes(port.written) == frame("ff ff fe 06 82 38 08 01 02 36")
    assert feetech.decode(replies[1].data[:2]) == 2048
    assert feetech.decode(replies[2].data[:2]) == 2047


def test_restart_sends_no_status_and_waits_for_none():
    port = RecordedPort()
    assert Client(port, protocol=FEETECH).reboot(1) is None
    assert bytes(port.written) == packet1(1, feetech.RESTART)


def test_sync_write_blocks_must_be_of_one_length():
    with pytest.raises(ValueError):
        Client(RecordedPort(), protocol=FEETECH).sync_write(42, {1: b"\x00\x08", 2: b"\x00"})


def test_protocol_1_has_no_sync_read_and_unknown_protocols_are_refused():
    with pytest.raises(CommError):
        Client(RecordedPort(), protocol=1).sync_read(0x38, 2, [1])
    with pytest.raises(ValueError):
        Client(RecordedPort(), protocol="scs")


def test_sign_magnitude_round_trips_and_matches_the_sdk():
    # FEETECH's SDK: Position = -Position; Position |= (1 << 15).
    assert feetech.to_sign_magnitude(-100, 15) == 100 | 0x8000
    assert feetech.from_sign_magnitude(100 | 0x8000, 15) == -100
    assert feetech.from_sign_magnitude(0x8000, 15) == 0  # "-0"
    for bit in (10, 11, 15):
        for value in (-(1 << bit) + 1, -1, 0, 1, (1 << bit) - 1):
            assert feetech.from_sign_magnitude(feetech.to_sign_magnitude(value, bit), bit) == value
    with pytest.raises(ValueError):
        feetech.to_sign_magnitude(1 << 10, 10)


def test_values_encode_in_the_series_byte_order():
    assert feetech.encode(2048, 2) == b"\x00\x08"
    assert feetech.encode(2048, 2, order="big") == b"\x08\x00"  # SCS: high byte first
    assert feetech.encode(-5, 2, sign_bit=15) == b"\x05\x80"
    assert feetech.decode(b"\x80\x05", order="big", sign_bit=15) == -5
