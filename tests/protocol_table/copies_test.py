"""The copies of the protocol table outside C++ agree with it.

The emulator's protocol table (emulator/wire/protocol_table.hpp) is printed as JSON by
dxlemu_print_protocol_table (argv[1]); the Python package (python/dxlemu/codec.py, feetech.py,
modbus.py) and the Wireshark dissector (scripts/dxlemu.lua) keep their own copies of the codes and
names, written from the protocol pages independently, so that each checks the other. This test fails
when a protocol or an instruction is added to, or changed in, one of them and not the others.
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from dxlemu import codec, feetech, modbus  # noqa: E402  (after the path is set)

# FEETECH constants in dxlemu.feetech named otherwise than the table's snake_case name.
FEETECH_ALIASES = {
    "RECOVERY": "parameter_recovery",
    "RESTART": "reboot",
    "BACKUP": "parameter_backup",
}
# DYNAMIXEL instruction constants dxlemu.codec defines (the others it does not send).
CODEC_INSTRUCTIONS = ["PING", "READ", "WRITE", "REG_WRITE", "ACTION", "FACTORY_RESET", "REBOOT",
                      "CLEAR", "STATUS", "SYNC_READ", "SYNC_WRITE", "BULK_READ", "BULK_WRITE"]
# dxlemu.modbus's function code constants: every function of the table, named as it names them.
MODBUS_FUNCTIONS = ["READ_HOLDING_REGISTERS", "READ_INPUT_REGISTERS", "WRITE_SINGLE_REGISTER",
                    "DIAGNOSTICS", "WRITE_MULTIPLE_REGISTERS", "READ_WRITE_MULTIPLE_REGISTERS"]
FEETECH_INSTRUCTIONS = ["PING", "READ", "WRITE", "REG_WRITE", "ACTION", "RECOVERY", "RESTART",
                        "BACKUP", "STATUS_RESET", "POSITION_CALIBRATION", "SYNC_READ",
                        "SYNC_WRITE"]


def load_table(program: str) -> dict[str, dict]:
    out = subprocess.run([program], check=True, capture_output=True, text=True).stdout
    return {row["spelling"]: row for row in json.loads(out)}


def lua_constants(text: str) -> dict[str, int]:
    """`local A, B = 0x01, 0x02` and `local A = 0x46` lines of the dissector."""
    values: dict[str, int] = {}
    for names, numbers in re.findall(r"^local ([A-Z0-9_, ]+) = ([0-9xA-Fa-f, ]+?)\s*(?:--.*)?$",
                                     text, re.M):
        for name, number in zip(names.split(","), numbers.split(",")):
            values[name.strip()] = int(number.strip(), 0)
    return values


def lua_table(text: str, name: str, constants: dict[str, int]) -> dict[int, str]:
    """The entries `[KEY] = "Title"` of `local name = { ... }`."""
    body = re.search(r"^local " + name + r" = \{(.*?)^\}", text, re.M | re.S)
    assert body, f"no table {name} in the dissector"
    out = {}
    for key, title in re.findall(r"\[([A-Z0-9_x]+)\] = \"([^\"]*)\"", body.group(1)):
        out[constants[key] if key in constants else int(key, 0)] = title
    return out


class CopiesAgree(unittest.TestCase):
    table: dict[str, dict]

    @classmethod
    def setUpClass(cls) -> None:
        cls.table = load_table(sys.argv[1])

    def codes(self, spelling: str) -> dict[str, int]:
        return {i["name"]: i["code"] for i in self.table[spelling]["instructions"]}

    def titles(self, spelling: str) -> dict[int, str]:
        return {i["code"]: i["title"] for i in self.table[spelling]["instructions"]}

    def test_the_table_has_the_protocols_the_copies_know(self) -> None:
        self.assertEqual(sorted(self.table), ["1", "2", feetech.PROTOCOL, modbus.PROTOCOL])

    def test_python_dynamixel_codes_are_the_tables(self) -> None:
        for spelling in ("1", "2"):
            codes = self.codes(spelling)
            for constant in CODEC_INSTRUCTIONS:
                self.assertEqual(getattr(codec, constant), codes[constant.lower()], constant)
        self.assertEqual(codec.BROADCAST_ID, self.table["2"]["broadcast_id"])
        self.assertEqual(list(codec.HEADER1), self.table["1"]["header"])
        self.assertEqual(list(codec.HEADER2), self.table["2"]["header"])
        self.assertEqual(codec.ALERT, self.table["2"]["alert_bit"])

    def test_python_feetech_codes_are_the_tables_every_one(self) -> None:
        codes = self.codes(feetech.PROTOCOL)
        names = {FEETECH_ALIASES.get(c, c.lower()) for c in FEETECH_INSTRUCTIONS}
        self.assertEqual(names, set(codes))
        for constant in FEETECH_INSTRUCTIONS:
            self.assertEqual(getattr(feetech, constant),
                             codes[FEETECH_ALIASES.get(constant, constant.lower())], constant)

    def test_python_modbus_codes_names_addresses_and_timing_are_the_tables(self) -> None:
        row = self.table[modbus.PROTOCOL]
        codes = self.codes(modbus.PROTOCOL)
        self.assertEqual({c.lower() for c in MODBUS_FUNCTIONS}, set(codes))
        for constant in MODBUS_FUNCTIONS:
            self.assertEqual(getattr(modbus, constant), codes[constant.lower()], constant)
        self.assertEqual(modbus.FUNCTION_NAMES, self.titles(modbus.PROTOCOL))
        self.assertEqual((row["name"], row["spelling"], row["number"]),
                         (modbus.PROTOCOL, modbus.PROTOCOL, 0))
        self.assertEqual(modbus.PROTOCOL_TYPE, row["type_value"])
        self.assertEqual(modbus.BROADCAST_ADDRESS, row["broadcast_id"])
        self.assertEqual((modbus.MIN_ADDRESS, modbus.MAX_ADDRESS),
                         (row["min_unicast_id"], row["max_unicast_id"]))
        self.assertEqual(modbus.REGISTER_BYTES, row["register_bytes"])
        self.assertEqual((modbus.MIN_FRAME, modbus.MAX_FRAME),
                         (row["min_length"], row["max_length"]))
        self.assertEqual(row["check"], "crc16_modbus")
        self.assertEqual(row["delimiting"], "silence")
        self.assertEqual((modbus.SILENCE_TENTHS, modbus.GAP_TENTHS, modbus.CHAR_BITS),
                         (row["silence_tenths"], row["gap_tenths"], row["char_bits"]))
        self.assertEqual(
            (modbus.FIXED_TIMING_ABOVE_BPS, modbus.FIXED_SILENCE_US, modbus.FIXED_GAP_US),
            (row["fixed_timing_above_bps"], row["fixed_silence_us"], row["fixed_gap_us"]))
        # Every exception code the emulator can send has its name in the package.
        sent = {code for code in row["status_codes"] if code != 0}
        self.assertLessEqual(sent, set(modbus.EXCEPTION_NAMES))

    def test_dissector_modbus_names_and_codes_are_the_tables_and_the_packages(self) -> None:
        text = (ROOT / "scripts" / "dxlemu.lua").read_text()
        constants = lua_constants(text)
        row = self.table[modbus.PROTOCOL]
        self.assertEqual(lua_table(text, "modbus_function_names", constants),
                         self.titles(modbus.PROTOCOL))
        # Exception names are no field of the table: the two copies check each other.
        self.assertEqual(lua_table(text, "modbus_exception_names", constants),
                         modbus.EXCEPTION_NAMES)
        self.assertEqual(constants["MODBUS"], row["value"])
        self.assertEqual(constants["MODBUS_BROADCAST"], row["broadcast_id"])
        self.assertEqual(constants["MODBUS_MIN_FRAME"], row["min_length"])
        self.assertEqual(constants["MODBUS_EXCEPTION_FLAG"], modbus.EXCEPTION_FLAG)

    def test_dissector_instruction_names_are_the_tables_titles(self) -> None:
        text = (ROOT / "scripts" / "dxlemu.lua").read_text()
        constants = lua_constants(text)
        self.assertEqual(lua_table(text, "instruction_names", constants), self.titles("2"))
        self.assertEqual(lua_table(text, "feetech_instruction_names", constants),
                         self.titles(feetech.PROTOCOL))
        self.assertEqual(constants["FEETECH"], self.table[feetech.PROTOCOL]["value"])
        self.assertEqual(constants["BROADCAST_ID"], self.table["2"]["broadcast_id"])
        self.assertEqual(constants["V1_MIN_LENGTH"], self.table["1"]["min_length"])
        self.assertEqual(constants["V2_MIN_LENGTH"], self.table["2"]["min_length"])

    def test_dissector_names_each_capture_protocol_byte_as_the_table_does(self) -> None:
        text = (ROOT / "scripts" / "dxlemu.lua").read_text()
        constants = lua_constants(text)
        field = re.search(r'ProtoField\.uint8\("dxlemu\.protocol".*?\{(.*?)\}', text, re.S)
        assert field, "no dxlemu.protocol field in the dissector"
        names = {}
        for key, name in re.findall(r"\[([A-Z0-9_x]+)\] = \"([^\"]*)\"", field.group(1)):
            names[constants[key] if key in constants else int(key, 0)] = name
        names.pop(0)  # "unknown": no protocol
        self.assertEqual(names, {row["value"]: row["name"] for row in self.table.values()})


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
