"""End-to-end tests of `dxlemu run --pcap FILE` and the Wireshark dissector scripts/dxlemu.lua
(docs/pcap.md): the real daemon writes a capture of real traffic over its PTY, Python checks the
file's structure, and tshark with the dissector decodes it.

Run as a script (`python3 pcap_test.py`). Without tshark (Debian package tshark) it fails at once:
the dissector is part of what it checks.
"""
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

from dxl_client import (Client, Control, Daemon, Port, assert_unanswered, crc16, dxlemu_command,
                        modbus, packet1, packet2)

PING, READ, WRITE, SYNC_READ, FAST_SYNC_READ, STATUS = 0x01, 0x02, 0x03, 0x82, 0x8A, 0x55
PRESENT_POSITION, GOAL_POSITION = 132, 116
TO_SERVOS, TO_CLIENT = 0, 1
# The capture's clock is stepped this far before each packet, so that every packet and its
# replies have a time of their own, known to the nanosecond.
STEP_NS = 1_234_567
FEETECH = 0x46  # the pseudo-header's protocol byte of a FEETECH port
MODBUS = 10  # the pseudo-header's protocol byte of a Modbus RTU port (Protocol Type 10)
LUA = Path(__file__).resolve().parents[2] / "scripts" / "dxlemu.lua"
TSHARK = shutil.which("tshark")

PCAP_MAGIC, LINKTYPE_USER0 = 0xA1B2C3D4, 147
GLOBAL_HEADER, RECORD_HEADER = struct.Struct("<IHHiIII"), struct.Struct("<IIII")


def read_pcap(path):
    """(global header fields, [(microseconds since the Unix epoch, bytes of the record)])."""
    data = Path(path).read_bytes()
    header = GLOBAL_HEADER.unpack_from(data)
    records, at = [], GLOBAL_HEADER.size
    while at < len(data):
        sec, usec, captured, original = RECORD_HEADER.unpack_from(data, at)
        at += RECORD_HEADER.size
        assert captured == original, (captured, original)
        records.append((sec * 1_000_000 + usec, data[at:at + captured]))
        at += captured
    return header, records


def write_pcap(path, records):
    """A capture as dxlemu writes it: `records` are (direction, protocol, port, line bytes)."""
    with open(path, "wb") as f:
        f.write(GLOBAL_HEADER.pack(PCAP_MAGIC, 2, 4, 0, 0, 262144, LINKTYPE_USER0))
        for i, (direction, protocol, port, line) in enumerate(records):
            body = bytes([1, direction, protocol, port]) + line
            f.write(RECORD_HEADER.pack(1_700_000_000 + i, 0, len(body), len(body)) + body)


def tshark(path, *fields):
    """One list per record: for each field, the list of its values in that record."""
    args = ["tshark", "-X", f"lua_script:{LUA}", "-r", str(path), "-T", "fields",
            "-E", "occurrence=a", "-E", "aggregator=|", "-E", "separator=\t"]
    for field in fields:
        args += ["-e", field]
    result = subprocess.run(args, capture_output=True, text=True, timeout=60)
    if result.returncode != 0 or "Lua: Error" in result.stderr:
        raise AssertionError("tshark failed: " + result.stderr)
    rows = []
    for line in result.stdout.splitlines():
        rows.append([value.split("|") if value else [] for value in line.split("\t")])
    return rows


def with_bad_crc(packet):
    return packet[:-2] + bytes([packet[-2] ^ 0xFF, packet[-1]])


class CaptureTest(unittest.TestCase):
    """The real daemon's capture of Ping, Read, Write, a bad CRC and a Sync Read, on a stepped
    clock (manual timing: replies at once, at their instruction's time)."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        link = os.path.join(cls.dir.name, "dxl0")
        cls.pcap = os.path.join(cls.dir.name, "capture.pcap")
        trace = os.path.join(cls.dir.name, "trace.jsonl")
        control_path = os.path.join(cls.dir.name, "control.sock")
        cls.started = time.time()
        daemon = Daemon("--link", link, "--pcap", cls.pcap, "--trace", trace,
                        "--timing", "manual", "--control", control_path)
        try:
            control = Control(control_path)
            port = Port(link)
            cls.sent = [packet2(1, PING),
                        packet2(2, READ, bytes([PRESENT_POSITION, 0, 4, 0])),
                        packet2(3, WRITE, bytes([GOAL_POSITION, 0, 0x00, 0x04, 0x00, 0x00])),
                        with_bad_crc(packet2(1, READ, bytes([PRESENT_POSITION, 0, 4, 0]))),
                        packet2(0xFE, SYNC_READ, bytes([PRESENT_POSITION, 0, 4, 0, 1, 2, 3]))]
            cls.replies = []
            cls.replies_per_packet = (1, 1, 1, 1, 3)
            for packet, replies in zip(cls.sent, cls.replies_per_packet):
                control.call("clock.step", ns=STEP_NS)
                port.write(packet)
                for _ in range(replies):
                    cls.replies.append(port.status2())
            port.close()
            control.close()
        finally:
            cls.exit_code = daemon.stop()
        with open(trace) as f:
            cls.trace = [json.loads(line) for line in f]

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_the_daemon_stops_cleanly_after_every_reply(self):
        self.assertEqual(self.exit_code, 0)
        self.assertEqual([r[0] for r in self.replies], [1, 2, 3, 1, 1, 2, 3])
        self.assertEqual(self.replies[3][1], 0x03)  # the bad CRC is answered with CRC Error

    def test_the_file_is_a_classic_pcap_with_one_record_per_packet_each_way(self):
        header, records = read_pcap(self.pcap)
        self.assertEqual(header, (PCAP_MAGIC, 2, 4, 0, 0, 262144, LINKTYPE_USER0))
        self.assertEqual(len(records), len(self.sent) + len(self.replies))
        # Same packets, same order as the JSON trace, which --trace writes from the same observer.
        self.assertEqual(len(records), len(self.trace))
        for (_, record), line in zip(records, self.trace):
            direction = TO_SERVOS if line["dir"] == "in" else TO_CLIENT
            self.assertEqual(record[:4], bytes([1, direction, line["protocol"], 0]))
            if "hex" in line:
                self.assertEqual(record[4:].hex(" ").upper(), line["hex"])
        instructions = [record[4:] for _, record in records if record[1] == TO_SERVOS]
        self.assertEqual(instructions, self.sent)  # the bad packet too, found among the bytes in
        times = [t for t, _ in records]
        self.assertEqual(times, sorted(times))
        # Wall-clock time at start plus simulated time.
        self.assertLess(abs(times[0] / 1e6 - self.started), 30)
        # Each packet and its replies at the time the clock was stepped to before it.
        stepped = [STEP_NS * (i + 1) for i, replies in enumerate(self.replies_per_packet)
                   for _ in range(1 + replies)]
        self.assertEqual([round(line["t"] * 1e9) for line in self.trace], stepped)
        for (t, _), line in zip(records, self.trace):
            # Both are the same simulated time; the capture's is cut to microseconds.
            self.assertAlmostEqual((t - times[0]) / 1e6, line["t"] - self.trace[0]["t"], delta=1.5e-6)

    def test_wireshark_decodes_directions_ids_instructions_and_addresses(self):
        rows = tshark(self.pcap, "dxlemu.direction", "dxlemu.port", "dxl.protocol", "dxl.id",
                      "dxl.instruction", "dxl.address", "dxl.data_length", "dxl.error",
                      "dxl.target_id")
        decoded = [tuple(tuple(values) for values in row) for row in rows]
        self.assertEqual(decoded, [
            (("0",), ("0",), ("2",), ("1",), ("0x01",), (), (), (), ()),
            (("1",), ("0",), ("2",), ("1",), ("0x55",), (), (), ("0x00",), ()),
            (("0",), ("0",), ("2",), ("2",), ("0x02",), ("132",), ("4",), (), ()),
            (("1",), ("0",), ("2",), ("2",), ("0x55",), (), (), ("0x00",), ()),
            (("0",), ("0",), ("2",), ("3",), ("0x03",), ("116",), ("4",), (), ()),
            (("1",), ("0",), ("2",), ("3",), ("0x55",), (), (), ("0x00",), ()),
            (("0",), ("0",), ("2",), ("1",), ("0x02",), ("132",), ("4",), (), ()),
            (("1",), ("0",), ("2",), ("1",), ("0x55",), (), (), ("0x03",), ()),
            (("0",), ("0",), ("2",), ("254",), ("0x82",), ("132",), ("4",), (), ("1", "2", "3")),
            (("1",), ("0",), ("2",), ("1",), ("0x55",), (), (), ("0x00",), ()),
            (("1",), ("0",), ("2",), ("2",), ("0x55",), (), (), ("0x00",), ()),
            (("1",), ("0",), ("2",), ("3",), ("0x55",), (), (), ("0x00",), ()),
        ])

    def test_wireshark_flags_the_bad_crc_and_only_it(self):
        rows = tshark(self.pcap, "dxl.crc.status", "_ws.expert.message")
        statuses = [row[0] for row in rows]
        self.assertEqual(statuses, [["1"]] * 6 + [["0"]] + [["1"]] * 5)
        bad = packet2(1, READ, bytes([PRESENT_POSITION, 0, 4, 0]))
        good_crc = crc16(bad[:-2])
        self.assertEqual(rows[6][1], [f"Bad CRC 0x{good_crc ^ 0xFF:04x}, expected 0x{good_crc:04x}"])
        self.assertEqual(rows[7][1], ["Status error 0x03"])  # the servo's CRC Error status
        self.assertEqual([row[1] for i, row in enumerate(rows) if i not in (6, 7)], [[]] * 10)


def daemon_speaks_modbus():
    """True when this dxlemu serves Modbus RTU (`dxlemu models --protocol modbus` lists models)."""
    result = subprocess.run(dxlemu_command("models", "--protocol", "modbus"), capture_output=True,
                            text=True, timeout=60)
    return result.returncode == 0 and "ph54-200-s500-r" in result.stdout


@unittest.skipUnless(daemon_speaks_modbus(), "this dxlemu does not serve --protocol modbus yet")
class ModbusCaptureTest(unittest.TestCase):
    """The real daemon's capture of a DYNAMIXEL-P speaking Modbus RTU: reads, a write, an
    exception response and a frame with a bad CRC (ignored), decoded by the dissector."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        link = os.path.join(cls.dir.name, "dxl0")
        cls.pcap = os.path.join(cls.dir.name, "capture.pcap")
        control_path = os.path.join(cls.dir.name, "control.sock")
        daemon = Daemon("--link", link, "--pcap", cls.pcap, "--servo", "ph54-200-s500-r:1",
                        "--protocol", "modbus", "--timing", "manual", "--control", control_path)
        try:
            control = Control(control_path)
            port = Port(link)
            client = Client(port, protocol=modbus.PROTOCOL)
            cls.model = client.ping(1).value
            cls.goal = client.read(1, 564, 4).value
            client.write_register(1, 0x0100, 1)  # Torque Enable
            try:
                client.read_registers(1, 0x7FFF, 1)
                cls.refusal = None
            except modbus.ModbusException as error:
                cls.refusal = error.code
            bad = bytearray(modbus.read_registers_request(1, 0, 1))
            bad[-1] ^= 0xFF
            assert_unanswered(control, port, bytes(bad))
            port.close()
            control.close()
        finally:
            cls.exit_code = daemon.stop()

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_the_servo_answers_as_a_modbus_server(self):
        self.assertEqual(self.exit_code, 0)
        self.assertEqual(self.model, 2020)  # PH54-200-S500-R
        self.assertEqual(self.refusal, modbus.ILLEGAL_DATA_ADDRESS)

    def test_every_record_is_a_modbus_frame_wireshark_decodes(self):
        _, records = read_pcap(self.pcap)
        self.assertEqual({record[2] for _, record in records}, {MODBUS})
        rows = tshark(self.pcap, "modbus_rtu.packet_type", "modbus_rtu.address",
                      "modbus_rtu.function", "modbus_rtu.exception_code",
                      "modbus_rtu.crc.status")
        self.assertEqual([row[:3] for row in rows], [
            [["0"], ["1"], ["0x03"]], [["1"], ["1"], ["0x03"]],  # Ping: Model Number
            [["0"], ["1"], ["0x03"]], [["1"], ["1"], ["0x03"]],  # Goal Position
            [["0"], ["1"], ["0x06"]], [["1"], ["1"], ["0x06"]],  # Torque Enable
            [["0"], ["1"], ["0x03"]], [["1"], ["1"], ["0x03"]],  # refused
            [["0"], ["1"], ["0x03"]],                            # bad CRC: no response
        ])
        self.assertEqual(rows[7][3], ["0x02"])
        self.assertEqual([row[4] for row in rows], [["1"]] * 8 + [["0"]])


class DissectorTest(unittest.TestCase):
    """The dissector on hand-made records: what the daemon writes rarely, or never."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)
        self.path = os.path.join(self.dir.name, "made.pcap")

    def decode(self, records, *fields):
        write_pcap(self.path, records)
        return tshark(self.path, *fields)

    def test_several_packets_and_garbage_in_one_record(self):
        line = (b"\x00\x13" + packet2(1, PING) + b"\xff" + packet2(2, READ, bytes([10, 0, 1, 0]))
                + b"\xfe\xfe")
        rows = self.decode([(TO_SERVOS, 0, 0, line)],
                           "dxl.id", "dxl.instruction", "dxl.garbage", "dxl.crc.status", "_ws.col.Info")
        self.assertEqual(rows[0][:4], [["1", "2"], ["0x01", "0x02"], ["0013", "ff", "fefe"],
                                       ["1", "1"]])
        self.assertIn("Instruction id=2 Read addr=10 len=1", rows[0][4][0])

    def test_protocol_1_instructions_and_statuses_with_their_checksums(self):
        bad = bytearray(packet1(4, WRITE, bytes([30, 0x00, 0x02])))
        bad[-1] ^= 0x01
        rows = self.decode([(TO_SERVOS, 1, 2, packet1(3, READ, bytes([36, 2]))),
                            (TO_CLIENT, 1, 2, bytes([0xFF, 0xFF, 3, 4, 0x24, 0x00, 0x02])
                             + bytes([~(3 + 4 + 0x24 + 0x02) & 0xFF])),
                            (TO_SERVOS, 1, 2, bytes(bad))],
                           "dxlemu.port", "dxl.protocol", "dxl.id", "dxl.instruction", "dxl.address",
                           "dxl.data_length", "dxl.error", "dxl.error.overheating", "dxl.params",
                           "dxl.checksum.status", "_ws.expert.message")
        self.assertEqual(rows[0][:10], [["2"], ["1"], ["3"], ["0x02"], ["36"], ["2"], [], [], ["2402"],
                                        ["1"]])
        self.assertEqual(rows[1][:10], [["2"], ["1"], ["3"], [], [], [], ["0x24"], ["1"], ["0002"],
                                        ["1"]])
        self.assertEqual(rows[1][10], ["Status error 0x24"])
        self.assertEqual(rows[2][3:6] + rows[2][9:10], [["0x03"], ["30"], ["2"], ["0"]])
        self.assertTrue(rows[2][10][0].startswith("Bad checksum"))

    def test_stuffed_parameters_are_unstuffed(self):
        # Writing FF FF FD to address 0x0100: the sender stuffs a FD after FF FF FD.
        packet = packet2(5, WRITE, bytes([0x00, 0x01, 0xFF, 0xFF, 0xFD]))
        self.assertIn(b"\xff\xff\xfd\xfd", packet[7:])
        rows = self.decode([(TO_SERVOS, 2, 0, packet)],
                           "dxl.address", "dxl.data_length", "dxl.data", "dxl.crc.status")
        self.assertEqual(rows[0], [["256"], ["3"], ["fffffd"], ["1"]])

    def test_a_fast_sync_read_reply_decodes_as_a_status_with_parameters(self):
        request = packet2(0xFE, FAST_SYNC_READ, bytes([PRESENT_POSITION, 0, 4, 0, 1, 2]))
        # protocol2.md "Fast Sync Read": one packet from 0xFE, a block per servo, each with its CRC.
        body = bytes([0xFF, 0xFF, 0xFD, 0x00, 0xFE, 0x00, 0x00, STATUS, 0x00, 1, 0, 8, 0, 0])
        first = crc16(body)
        body += bytes([first & 0xFF, first >> 8, 0x00, 2, 0, 8, 0, 0])
        length = len(body) - 7 + 2
        body = body[:5] + bytes([length & 0xFF, length >> 8]) + body[7:]
        crc = crc16(body)
        reply = body + bytes([crc & 0xFF, crc >> 8])
        rows = self.decode([(TO_SERVOS, 2, 0, request), (TO_CLIENT, 2, 0, reply)],
                           "dxl.id", "dxl.instruction", "dxl.error", "dxl.params", "dxl.crc.status",
                           "dxl.target_id", "_ws.expert.message")
        self.assertEqual(rows[0][:2] + rows[0][5:6], [["254"], ["0x8a"], ["1", "2"]])
        self.assertEqual(rows[1][:5], [["254"], ["0x55"], ["0x00"],
                                       [reply[9:-2].hex()], ["1"]])
        self.assertIn("Fast Sync/Bulk Read reply", rows[1][6][0])

    def test_feetech_records_decode_as_feetech_packets(self):
        # protocol-ft-scs.md 4.7: Sync Read of 8 bytes at 0x38 from IDs 1 and 2, and the replies.
        request = bytes.fromhex("ff ff fe 06 82 38 08 01 02 36")
        replies = bytes.fromhex("ff ff 01 0a 00 00 08 00 00 00 00 79 1e 55"
                                "ff ff 02 0a 00 ff 07 00 00 00 00 77 23 53")
        rows = self.decode([(TO_SERVOS, FEETECH, 1, request), (TO_CLIENT, FEETECH, 1, replies)],
                           "dxlemu.protocol", "feetech.id", "feetech.instruction",
                           "feetech.address", "feetech.data_length", "feetech.target_id",
                           "feetech.error", "feetech.checksum.status", "dxl.id",
                           "_ws.col.Protocol", "_ws.col.Info")
        self.assertEqual(rows[0][:9], [["70"], ["254"], ["0x82"], ["56"], ["8"], ["1", "2"], [],
                                       ["1"], []])
        self.assertEqual(rows[0][9], ["FEETECH"])
        self.assertIn("Instruction id=254 Sync Read addr=56 len=8 ids=1,2", rows[0][10][0])
        self.assertEqual(rows[1][1:2] + rows[1][6:8], [["1", "2"], ["0x00", "0x00"], ["1", "1"]])

    def test_feetech_names_status_bits_id_253_and_a_bad_checksum(self):
        # ID 253 (0xFD) is a FEETECH unicast ID, not the start of a 2.0 header there.
        ping_253 = packet1(0xFD, PING)
        restart = packet1(1, 0x08)
        status_reset = packet1(1, 0x0A)
        hot_overloaded = packet1(1, 0x24)  # a status: error byte overheat | overload
        bad = bytearray(packet1(2, READ, bytes([56, 2])))
        bad[-1] ^= 0x01
        rows = self.decode([(TO_SERVOS, FEETECH, 0, ping_253 + restart + status_reset),
                            (TO_CLIENT, FEETECH, 0, hot_overloaded),
                            (TO_SERVOS, FEETECH, 0, bytes(bad))],
                           "feetech.id", "feetech.instruction", "feetech.error",
                           "feetech.error.overheat", "feetech.error.overload",
                           "feetech.error.current", "feetech.checksum.status", "dxl.garbage",
                           "_ws.col.Info", "_ws.expert.message")
        self.assertEqual(rows[0][:2], [["253", "1", "1"], ["0x01", "0x08", "0x0a"]])
        self.assertEqual(rows[0][7], [])
        self.assertIn("Instruction id=1 Restart", rows[0][8][0])
        self.assertIn("Instruction id=1 Status Reset", rows[0][8][0])
        self.assertEqual(rows[1][2:6], [["0x24"], ["1"], ["1"], ["0"]])
        self.assertEqual(rows[1][9], ["Status error 0x24"])
        self.assertEqual(rows[2][6], ["0"])
        self.assertTrue(rows[2][9][0].startswith("Bad checksum"))

    def test_modbus_records_decode_as_modbus_rtu_frames(self):
        # modbus-rtu.md "Frames (computed)": read Goal Position, its answer, Goal Position = 2048,
        # the answer, Torque Enable on broadcast, a read refused with Illegal Data Address.
        read_goal = bytes.fromhex("01 03 01 1A 00 02 E4 30")
        write_goal = bytes.fromhex("01 10 01 1A 00 02 04 08 00 00 00 7D 2C")
        torque_on = modbus.write_register_request(0, 0x0100, 1)
        goal = modbus.frame(1, 3, bytes.fromhex("04 08 00 00 00"))
        rows = self.decode([(TO_SERVOS, MODBUS, 0, read_goal),
                            (TO_CLIENT, MODBUS, 0, goal),
                            (TO_SERVOS, MODBUS, 0, write_goal),
                            (TO_CLIENT, MODBUS, 0, modbus.frame(1, 0x10, write_goal[2:6])),
                            (TO_SERVOS, MODBUS, 0, torque_on),
                            (TO_SERVOS, MODBUS, 0, bytes.fromhex("01 03 00 00 00 0A C5 CD")),
                            (TO_CLIENT, MODBUS, 0, bytes.fromhex("01 83 02 C0 F1"))],
                           "dxlemu.protocol", "modbus_rtu.packet_type", "modbus_rtu.address",
                           "modbus_rtu.function", "modbus_rtu.exception", "modbus_rtu.start",
                           "modbus_rtu.table_address", "modbus_rtu.quantity",
                           "modbus_rtu.byte_count", "modbus_rtu.value",
                           "modbus_rtu.exception_code", "modbus_rtu.crc.status", "dxl.id",
                           "_ws.col.Protocol", "_ws.col.Info", "_ws.expert.message")
        decoded = [row[:13] for row in rows]
        self.assertEqual(decoded, [
            [["10"], ["0"], ["1"], ["0x03"], ["0"], ["282"], ["564"], ["2"], [], [], [], ["1"], []],
            [["10"], ["1"], ["1"], ["0x03"], ["0"], [], [], [], ["4"], ["2048", "0"], [], ["1"],
             []],
            [["10"], ["0"], ["1"], ["0x10"], ["0"], ["282"], ["564"], ["2"], ["4"], ["2048", "0"],
             [], ["1"], []],
            [["10"], ["1"], ["1"], ["0x10"], ["0"], ["282"], ["564"], ["2"], [], [], [], ["1"], []],
            [["10"], ["0"], ["0"], ["0x06"], ["0"], [], ["512"], [], [], ["1"], [], ["1"], []],
            [["10"], ["0"], ["1"], ["0x03"], ["0"], ["0"], ["0"], ["10"], [], [], [], ["1"], []],
            [["10"], ["1"], ["1"], ["0x03"], ["1"], [], [], [], [], [], ["0x02"], ["1"], []],
        ])
        self.assertEqual({row[13][0] for row in rows}, {"Modbus RTU"})
        self.assertIn("Request addr=1 Read Holding Registers start=282 qty=2", rows[0][14][0])
        self.assertIn("Response addr=1 Read Holding Registers values=2048,0", rows[1][14][0])
        self.assertIn("Request addr=0 Write Single Register reg=256 value=1", rows[4][14][0])
        self.assertIn("exception 0x02 Illegal Data Address", rows[6][14][0])
        self.assertEqual(rows[6][15], ["Exception 0x02 Illegal Data Address"])
        self.assertEqual([row[15] for row in rows[:6]], [[]] * 6)

    def test_modbus_diagnostics_read_write_a_bad_crc_and_a_short_frame(self):
        echo = modbus.diagnostics_request(7, b"\x12\x34")
        read_write = modbus.read_write_registers_request(7, 0, 1, 256, [1])
        bad = bytearray(bytes.fromhex("01 06 01 00 00 01 49 F6"))
        bad[-2] ^= 0xFF
        rows = self.decode([(TO_SERVOS, MODBUS, 0, echo), (TO_CLIENT, MODBUS, 0, echo),
                            (TO_SERVOS, MODBUS, 0, read_write),
                            (TO_SERVOS, MODBUS, 0, bytes(bad)),
                            (TO_SERVOS, MODBUS, 0, b"\x01\x03")],
                           "modbus_rtu.packet_type", "modbus_rtu.subfunction", "modbus_rtu.data",
                           "modbus_rtu.read_start", "modbus_rtu.read_quantity",
                           "modbus_rtu.write_start", "modbus_rtu.write_quantity",
                           "modbus_rtu.crc.status", "modbus_rtu.truncated", "_ws.expert.message")
        self.assertEqual(rows[0][:3] + rows[0][7:8], [["0"], ["0x0000"], ["1234"], ["1"]])
        self.assertEqual(rows[1][:3] + rows[1][7:8], [["1"], ["0x0000"], ["1234"], ["1"]])
        self.assertEqual(rows[2][3:8], [["0"], ["1"], ["256"], ["1"], ["1"]])
        good = modbus.crc16(bad[:-2])
        self.assertEqual(rows[3][7], ["0"])
        self.assertEqual(rows[3][9], [f"Bad CRC 0x{good ^ 0xFF:04x}, expected 0x{good:04x}"])
        self.assertEqual(rows[4][8:], [["0103"], ["Frame shorter than 4 bytes"]])

    def test_an_incomplete_packet_at_the_end_is_flagged(self):
        rows = self.decode([(TO_SERVOS, 2, 0, packet2(1, PING) + packet2(2, PING)[:6])],
                           "dxl.id", "dxl.truncated", "_ws.expert.message")
        self.assertEqual(rows[0][:2], [["1"], ["fffffd000203"]])
        self.assertEqual(rows[0][2], ["Incomplete packet"])


if __name__ == "__main__":
    if not TSHARK:
        sys.exit("pcap_test: tshark not found (Debian package tshark): the dissector cannot be tested")
    unittest.main(verbosity=2)
