"""The protocol client against the real daemon over its PTY."""
import pytest

from dxlemu import CommTimeout
from dxlemu.protocol import ALERT, PING, packet2

TORQUE_ENABLE, HARDWARE_ERROR_STATUS, GOAL_POSITION, PRESENT_POSITION = 64, 70, 116, 132
XM430_W350 = 1020
BOOT_NS = 400_000_000  # a servo's boot time after Reboot (docs/servo.md)

# Manual timing: replies go out at once and are never dropped as late on a loaded machine, and
# nothing moves or cools unless a test steps the clock. (The fixture's default is fast timing.)
pytestmark = pytest.mark.dxlemu(timing="manual")


def test_ping_read_write_and_sync_read(dxlemu):
    with dxlemu.client() as client:
        ping = client.ping(1)
        assert (int.from_bytes(ping.data[:2], "little"), ping.error) == (XM430_W350, 0)
        assert client.read(2, PRESENT_POSITION, 4).value == 2048
        assert client.write_int(2, GOAL_POSITION, 1000, 4) == (b"", 0)
        assert client.read(2, GOAL_POSITION, 4).signed == 1000
        replies = client.sync_read(PRESENT_POSITION, 4, [3, 1])
        assert list(replies) == [3, 1] and replies[1].value == 2048


def test_an_absent_servo_times_out(dxlemu):
    with dxlemu.client(timeout=0.1) as client:
        with pytest.raises(CommTimeout):
            client.ping(9)


def test_reboot_answers_then_the_servo_is_silent_while_it_boots(dxlemu):
    with dxlemu.client() as client:
        assert client.reboot(3).error == 0
        client.send(3, PING)
        with pytest.raises(CommTimeout):
            client.receive(3, timeout=0.1)
        dxlemu.control.clock_step(ns=BOOT_NS - 1)
        client.send(3, PING)
        with pytest.raises(CommTimeout):
            client.receive(3, timeout=0.1)
        dxlemu.control.clock_step(ns=1)
        assert client.ping(3).error == 0  # booted


def test_the_alert_bit_follows_hardware_error_status(dxlemu):
    dxlemu.control.set(1, "hardware_error_status", 0x04)
    with dxlemu.client() as client:
        reply = client.read(1, HARDWARE_ERROR_STATUS, 1)
        assert reply.alert and reply.error == ALERT and reply.value == 0x04


def test_a_packet_with_a_bad_crc_gets_a_crc_error_status(dxlemu):
    with dxlemu.client() as client:
        client.port.write(packet2(1, PING)[:-1] + b"\x00")
        assert client.receive(1).error == 0x03  # CRC Error


@pytest.mark.dxlemu(servos=["ax-12a:5"], timing="manual")
def test_protocol_1(dxlemu):
    with dxlemu.client(baud=1000000, protocol=1) as client:
        assert client.ping(5) == (b"", 0)
        assert client.read(5, 0, 2).value == 12  # AX-12A model number
        assert client.write(5, 25, b"\x01").error == 0

