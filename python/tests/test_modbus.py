"""Modbus RTU in the package, without the emulator: the frames of modbus-rtu.md's "Frames
(computed)" table, CRC-16/MODBUS's check value, response parsing with exception responses, and
the client's register mapping on a port whose responses are canned bytes."""
import pytest

from dxlemu import modbus
from dxlemu.modbus import ModbusException
from dxlemu.protocol import MODBUS, BadPacket, Client, CommError, CommTimeout


def frame(text: str) -> bytes:
    return bytes.fromhex(text)


class CannedPort:
    """A port whose responses are canned bytes, handed out by Port.read's rule (up to `count`
    bytes, whatever is there); records what the client writes."""

    def __init__(self, *responses: bytes):
        self.written: list[bytes] = []
        self.responses = list(responses)
        self.pending = b""

    def flush_input(self) -> None:
        self.pending = b""

    def write(self, data: bytes) -> None:
        self.written.append(bytes(data))
        if self.responses:
            self.pending = self.responses.pop(0)

    def read(self, count: int, timeout: float = 1.0) -> bytes:
        out, self.pending = self.pending[:count], self.pending[count:]
        return out


def test_crc_check_value():
    assert modbus.crc16(b"123456789") == 0x4B37


@pytest.mark.parametrize("built, golden", [
    # read 10 holding registers from 0, server 1
    (lambda: modbus.read_registers_request(1, 0, 10), "01 03 00 00 00 0A C5 CD"),
    # the spec's example request: server 17, read 3 registers from 108
    (lambda: modbus.read_registers_request(17, 0x6B, 3), "11 03 00 6B 00 03 76 87"),
    # read Model Number and Model Information's first word, server 1
    (lambda: modbus.read_registers_request(1, 0, 2), "01 03 00 00 00 02 C4 0B"),
    # read Goal Position (2 registers at 0x011A), server 1
    (lambda: modbus.read_registers_request(1, 0x011A, 2), "01 03 01 1A 00 02 E4 30"),
    # Torque Enable on (register 0x0100 = 0x0001), server 1
    (lambda: modbus.write_register_request(1, 0x0100, 1), "01 06 01 00 00 01 49 F6"),
    # Goal Position = 2048 (registers 0x011A-0x011B = 0x0800, 0x0000), server 1
    (lambda: modbus.write_registers_request(1, 0x011A, [0x0800, 0]),
     "01 10 01 1A 00 02 04 08 00 00 00 7D 2C"),
    # the spec example's response (0x022B, 0x0000, 0x0064)
    (lambda: modbus.frame(17, 3, bytes([6]) + modbus.register_bytes([0x022B, 0, 0x64])),
     "11 03 06 02 2B 00 00 00 64 C8 BA"),
    # exception: Illegal Data Address to a read, server 1
    (lambda: modbus.frame(1, 0x83, bytes([2])), "01 83 02 C0 F1"),
])
def test_frames_match_the_computed_table(built, golden):
    assert built() == frame(golden)


def test_the_spec_examples_response_parses_into_its_registers():
    request, response = frame("11 03 00 6B 00 03 76 87"), frame("11 03 06 02 2B 00 00 00 64 C8 BA")
    assert modbus.response_length(request) == len(response)
    parsed = modbus.parse_response(request, response)
    assert (parsed.address, parsed.function) == (17, 3)
    assert modbus.registers(parsed.data[1:]) == [0x022B, 0, 0x64]


def test_an_exception_response_raises_with_its_code_and_name():
    request = frame("01 03 00 00 00 0A C5 CD")
    with pytest.raises(ModbusException) as caught:
        modbus.parse_response(request, frame("01 83 02 C0 F1"))
    error = caught.value
    assert (error.address, error.function, error.code, error.name) == (
        1, 3, modbus.ILLEGAL_DATA_ADDRESS, "Illegal Data Address")
    assert "Illegal Data Address" in str(error) and "Read Holding Registers" in str(error)
    assert modbus.exception_name(0x04) == "Server Device Failure"
    assert modbus.exception_name(0x42) == "exception 0x42"


@pytest.mark.parametrize("response, why", [
    ("01 83 02 C0 F0", "bad CRC"),
    ("02 03 04 00 00 00 00", "another server"),
    ("01 04 04 00 00 00 00", "another function"),
    ("01 03 02 00 00", "too short for the registers asked"),
    ("01 03 03 00 00 00", "byte count"),
])
def test_responses_that_do_not_answer_the_request_are_bad_packets(response, why):
    request = modbus.read_registers_request(1, 0, 2)
    raw = frame(response)
    if why != "bad CRC":
        raw = modbus.frame(raw[0], raw[1], raw[2:])
    with pytest.raises(BadPacket):
        modbus.parse_response(request, raw)


def test_write_responses_must_echo_the_request():
    request = frame("01 06 01 00 00 01 49 F6")
    assert modbus.parse_response(request, request).data == request[2:-2]
    with pytest.raises(BadPacket):
        modbus.parse_response(request, modbus.write_register_request(1, 0x0100, 0))
    request = frame("01 10 01 1A 00 02 04 08 00 00 00 7D 2C")
    assert modbus.parse_response(request, modbus.frame(1, 0x10, frame("01 1A 00 02")))
    with pytest.raises(BadPacket):
        modbus.parse_response(request, modbus.frame(1, 0x10, frame("01 1A 00 01")))


def test_requests_out_of_their_ranges_are_refused():
    with pytest.raises(ValueError):
        modbus.read_registers_request(1, 0, 126)
    with pytest.raises(ValueError):
        modbus.read_registers_request(1, 0, 0)
    with pytest.raises(ValueError):
        modbus.read_registers_request(1, 0xFFFF, 2)
    with pytest.raises(ValueError):
        modbus.read_registers_request(1, 0, 1, function=0x06)
    with pytest.raises(ValueError):
        modbus.write_registers_request(1, 0, [0] * 124)
    with pytest.raises(ValueError):
        modbus.write_register_request(1, 0, 0x10000)
    with pytest.raises(ValueError):
        modbus.read_write_registers_request(1, 0, 1, 0, [0] * 122)
    assert modbus.write_register_request(1, 0, -1)[4:6] == b"\xff\xff"


def test_table_bytes_are_little_endian_within_each_register():
    # Goal Position 2048 at table address 564 = registers 282 and 283 (0x0800, 0x0000).
    assert modbus.table_registers((2048).to_bytes(4, "little")) == [0x0800, 0x0000]
    assert modbus.table_bytes([0x0800, 0x0000]) == (2048).to_bytes(4, "little")
    assert modbus.register_bytes([0x0800, 0x0000]) == frame("08 00 00 00")


def test_rtu_timing_follows_the_character_time_then_fixed_values():
    assert modbus.silence_seconds(9600) == pytest.approx(3.5 * 11 / 9600)
    assert modbus.gap_seconds(19200) == pytest.approx(1.5 * 11 / 19200)
    assert modbus.silence_seconds(57600) == pytest.approx(1750e-6)
    assert modbus.gap_seconds(1000000) == pytest.approx(750e-6)


def test_read_response_reads_by_expected_and_exception_length():
    request = modbus.read_registers_request(1, 0, 2)
    normal = modbus.frame(1, 3, frame("04 0C 04 00 00"))
    port = CannedPort()
    port.pending = normal + b"\x99"  # a byte after the frame stays unread
    assert modbus.read_response(port.read, request, 0.1) == normal and port.pending == b"\x99"
    port.pending = frame("01 83 02 C0 F1") + normal
    assert modbus.read_response(port.read, request, 0.1) == frame("01 83 02 C0 F1")
    port.pending = b""
    assert modbus.read_response(port.read, request, 0.1) is None
    port.pending = normal[:5]
    with pytest.raises(BadPacket):
        modbus.read_response(port.read, request, 0.1)


def test_the_client_pings_reads_and_writes_table_bytes_as_registers():
    # PH54-200-S500-R: Model Number 2,020 (0x07E4) in register 0.
    port = CannedPort(modbus.frame(1, 3, frame("02 07 E4")),
                      modbus.frame(1, 3, frame("04 08 00 00 00")),
                      modbus.frame(1, 0x10, frame("01 1A 00 02")),
                      frame("01 06 01 00 00 01 49 F6"))
    client = Client(port, protocol=MODBUS)
    ping = client.ping(1)
    assert ping == (b"\xe4\x07", 0) and ping.value == 2020
    assert port.written[0] == frame("01 03 00 00 00 01 84 0A")
    assert client.read(1, 564, 4).value == 2048
    assert port.written[1] == frame("01 03 01 1A 00 02 E4 30")
    assert client.write_int(1, 564, 2048, 4) == (b"", 0)
    assert port.written[2] == frame("01 10 01 1A 00 02 04 08 00 00 00 7D 2C")
    assert client.write(1, 512, b"\x01\x00") == (b"", 0)
    assert port.written[3] == frame("01 06 01 00 00 01 49 F6")


def test_the_client_refuses_odd_addresses_and_lengths():
    client = Client(CannedPort(), protocol=MODBUS)
    for address, length in ((513, 2), (512, 1), (512, 3), (512, 0)):
        with pytest.raises(ValueError):
            client.read(1, address, length)
    with pytest.raises(ValueError):
        client.write(1, 513, b"\x01\x00")
    with pytest.raises(ValueError):
        client.write(1, 512, b"\x01")


def test_register_methods_and_their_exceptions():
    port = CannedPort(modbus.frame(3, 4, frame("02 12 34")),
                      modbus.frame(3, 0x17, frame("04 00 01 00 02")),
                      modbus.diagnostics_request(3, b"\xab\xcd"),
                      modbus.frame(3, 0x86, bytes([modbus.SERVER_DEVICE_FAILURE])))
    client = Client(port, protocol=MODBUS)
    assert client.read_registers(3, 7, 1, function=modbus.READ_INPUT_REGISTERS) == [0x1234]
    assert client.read_write_registers(3, 10, 2, 20, [5, 6]) == [1, 2]
    assert port.written[1] == modbus.read_write_registers_request(3, 10, 2, 20, [5, 6])
    assert client.diagnostics_echo(3, b"\xab\xcd") == b"\xab\xcd"
    with pytest.raises(ModbusException) as caught:
        client.write_register(3, 6, 1)
    assert (caught.value.code, caught.value.name) == (4, "Server Device Failure")


def test_broadcast_writes_wait_for_nothing_and_broadcast_reads_are_refused():
    port = CannedPort()
    client = Client(port, protocol=MODBUS, timeout=5.0)  # a wait would show as a timeout
    assert client.write(0, 512, b"\x01\x00") is None
    client.write_registers(0, 282, [0x0800, 0])
    assert port.written == [frame("00 06 01 00 00 01") + port.written[0][-2:],
                            modbus.write_registers_request(0, 282, [0x0800, 0])]
    with pytest.raises(ValueError):
        client.read_registers(0, 0, 1)
    with pytest.raises(ValueError):
        client.ping(0)


def test_silence_times_out_and_dynamixel_only_calls_are_refused():
    client = Client(CannedPort(), protocol=MODBUS, timeout=0.01)
    with pytest.raises(CommTimeout):
        client.ping(5)
    for call in (lambda: client.reboot(1), lambda: client.sync_read(0, 2, [1]),
                 lambda: client.sync_write(0, {1: b"\x00\x00"}), lambda: client.receive(1)):
        with pytest.raises(CommError):
            call()
    with pytest.raises(CommError):
        Client(CannedPort(), protocol=2).read_registers(1, 0, 1)
