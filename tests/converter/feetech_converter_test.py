"""Unit tests of the FEETECH model converter (scripts/feetech_converter): the reading of a
reference file's tables, the items made of the wiki's rows (keys, sizes, areas, sign bits, ranges,
initial values and their notes), the comparison with lerobot, and the validation rules. Reference
files are written into a temporary directory, so ../shared/reference is not needed."""
import copy
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "scripts"))

from feetech_converter import decisions  # noqa: E402
from feetech_converter.builder import build_model  # noqa: E402
from feetech_converter.items import parse_range  # noqa: E402
from feetech_converter.reference import read_reference  # noqa: E402
from feetech_converter.validation import check_model_numbers, validate  # noqa: E402

HEADER = ("| Address (DEC) | Address (HEX) | Function | Bytes | Initial value | Access | Range | Unit | Description |\n"
          "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n")

# A small STS-like reference file: the wiki's table in its sections, a lerobot table.
PAGE = (
    "# TEST — memory table\n\n## Model facts\n\ntext\n\n## Table A — FEETECH STS family memory table (verbatim)\n\n"
    "##### 2.1 Version Information\n\n" + HEADER +
    "| 0 | 0x00 | Firmware major version | 1 | – | R |  |  |  |\n"
    "| 1 | 0x01 | Firmware minor version | 1 | – | R |  |  |  |\n"
    "| 3 | 0x03 | Servo major version | 1 | – | R |  |  |  |\n"
    "| 4 | 0x04 | Servo minor version | 1 | – | R |  |  |  |\n\n"
    "##### 2.2 EPROM Configuration\n\n" + HEADER +
    "| 5 | 0x05 | Servo ID | 1 | 1 | R/W | 0~253 | ID | Unique |\n"
    "| 6 | 0x06 | Baud rate | 1 | 0 | R/W | 0~7 | None | codes |\n"
    "| 7 | 0x07 | Reserved | 1 | – | R/W | – | – |  |\n"
    "| 16 | 0x10 | Maximum torque | 2 | 1000 | R/W | 0~1000 | 0.1% | |\n"
    "| 18 | 0x12 | Phase | 1 | – | R/W | 0~254 | None | |\n\n"
    "##### 2.3 SRAM Control\n\n" + HEADER +
    "| 44 | 0x2C | PWM open-loop speed | 2 | 1000 | R/W | 0~1000 | 0.1% | BIT10 is the direction bit |\n"
    "| 48 | 0x30 | Torque limit | 2 | Maximum torque (16), default 1000 | R/W | 0~1000 | 0.1% | |\n"
    "| 50~54 | 0x32~0x36 | Undefined | 1 | – | R/W | – | – |  |\n\n"
    "##### 2.4 SRAM Feedback\n\n" + HEADER +
    "| 56 | 0x38 | Present position | 2 | – | R | – | 0.087° | BIT15 is the direction bit |\n\n"
    "## Table C — lerobot control table for `test`\n\n"
    "| area (source comment) | data_name | (address, size_byte) | source comment |\n| --- | --- | --- | --- |\n"
    "| EPROM | `ID` | (5, 1) |  |\n| EPROM | `Max_Torque_Limit` | (16, 1) |  |\n"
    "| SRAM | `Goal_Position_2` | (71, 2) | read-only |\n")


def model(**changes) -> decisions.Model:
    """The STS3215 decisions for the test file."""
    m = copy.deepcopy(next(m for m in decisions.MODELS if m.name == "sts3215"))
    m.reference = "test.md"
    for k, v in changes.items():
        setattr(m, k, v)
    return m


class Converted:
    """The test page converted with the STS family's decisions."""

    def __init__(self, page: str = PAGE, **changes):
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "test.md"
            path.write_text(page, encoding="utf-8")
            self.ref = read_reference(path)
        self.model = build_model(self.ref, model(**changes))
        self.items = {i["address"]: i for i in self.model["items"]}


class ReferenceTest(unittest.TestCase):
    def test_rows_keep_their_section_and_cells(self):
        c = Converted()
        rows = {r.address: r for r in c.ref.wiki}
        self.assertEqual(rows["16"].section, "EPROM Configuration")
        self.assertEqual(rows["48"].initial, "Maximum torque (16), default 1000")
        self.assertEqual([(e.name, e.address, e.size) for e in c.ref.lerobot],
                         [("ID", 5, 1), ("Max_Torque_Limit", 16, 1), ("Goal_Position_2", 71, 2)])

    def test_a_file_without_the_wiki_table_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "x.md"
            path.write_text("# nothing\n\n## Model facts\n", encoding="utf-8")
            with self.assertRaisesRegex(ValueError, "no 'Table A'"):
                read_reference(path)

    def test_an_unknown_section_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "x.md"
            path.write_text(PAGE.replace("2.3 SRAM Control", "2.3 Elsewhere"), encoding="utf-8")
            with self.assertRaisesRegex(ValueError, "unknown section 'Elsewhere'"):
                read_reference(path)

    def test_ranges_read_as_printed(self):
        self.assertEqual(parse_range("0~4094"), (0, 4094))
        self.assertEqual(parse_range("-32767~32767"), (-32767, 32767))
        self.assertEqual(parse_range("40 ~ 59"), (40, 59))
        self.assertIsNone(parse_range("–"))
        with self.assertRaises(ValueError):
            parse_range("0/50~253")


class ItemsTest(unittest.TestCase):
    def test_keys_sizes_areas_and_access(self):
        items = Converted().items
        self.assertEqual(items[5]["key"], "id")
        self.assertEqual(items[16]["key"], "maximum_torque")
        self.assertEqual((items[16]["area"], items[16]["access"]), ("EEPROM", "RW"))
        self.assertEqual((items[56]["area"], items[56]["access"]), ("RAM", "R"))

    def test_addresses_3_and_4_are_one_model_number_word(self):
        items = Converted().items
        self.assertEqual((items[3]["key"], items[3]["size"], items[3]["initial"]), ("model_number", 2, 777))
        self.assertNotIn(4, items)

    def test_undefined_rows_are_gaps_and_the_return_delay_is_added(self):
        items = Converted().items
        self.assertNotIn(50, items)
        self.assertEqual(items[7]["key"], "return_delay_time")
        self.assertIn("Reserved", items[7]["note"])

    def test_a_direction_bit_makes_a_sign_magnitude_item_with_the_negative_range(self):
        items = Converted().items
        self.assertEqual(items[44]["sign_bit"], 10)
        self.assertEqual((items[44]["min"], items[44]["max"]), (-1000, 1000))
        self.assertIn("sign_bit: 10", items[44]["note"])
        self.assertEqual(items[56]["sign_bit"], 15)
        self.assertNotIn("min", items[56])  # the full width of the encoding

    def test_initial_values_printed_decided_or_copied(self):
        items = Converted().items
        self.assertEqual(items[16]["initial"], 1000)
        self.assertEqual(items[18]["initial"], 12)
        self.assertTrue(items[18]["note"].startswith("initial: the wiki prints '–'"))
        self.assertEqual(items[48]["initial_from"], "maximum_torque")
        self.assertEqual(items[0]["initial"], 3)

    def test_an_initial_with_no_decision_is_refused(self):
        page = PAGE.replace("| 16 | 0x10 | Maximum torque | 2 | 1000 |", "| 17 | 0x11 | Mystery | 1 | – |")
        with self.assertRaisesRegex(ValueError, "address 17 .Mystery.: the wiki prints initial '–'"):
            Converted(page)

    def test_two_direction_bits_need_a_decision(self):
        page = PAGE.replace("| 0.1% | BIT10 is the direction bit |", "| 0.1% | BIT15 is the direction bit; BIT10 is the direction bit |")
        with self.assertRaisesRegex(ValueError, r"direction bits \[10, 15\]"):
            Converted(page)


class ModelTest(unittest.TestCase):
    def test_model_fields(self):
        m = Converted().model
        self.assertEqual(m["protocols"], ["feetech"])
        self.assertEqual(m["byte_order"], "little")
        self.assertEqual([b["bps"] for b in m["baud_rates"]][5:], [76800, 57600, 38400])
        self.assertEqual(m["motion"]["stall_torque_nm"], round(19 * decisions.KG_CM_NM, 4))

    def test_lerobot_differences_are_noted(self):
        notes = Converted().model["notes"]
        self.assertIn("lerobot: Max_Torque_Limit (16, 1): maximum_torque there is 2 bytes; the model follows "
                      "FEETECH's table", notes)
        self.assertTrue(any(n.startswith("lerobot: Goal_Position_2 (71, 2): an address") for n in notes))
        self.assertFalse(any(n.startswith("lerobot: ID ") for n in notes))

    def test_the_converted_model_passes_validation(self):
        validate(Converted().model)


class ValidationTest(unittest.TestCase):
    def broken(self, change) -> str:
        m = copy.deepcopy(Converted().model)
        change(m)
        with self.assertRaises(ValueError) as caught:
            validate(m)
        return str(caught.exception)

    def item(self, m, key):
        return next(i for i in m["items"] if i["key"] == key)

    def test_refusals(self):
        self.assertIn("overlaps", self.broken(lambda m: self.item(m, "maximum_torque").update(size=4)))
        self.assertIn("sign_bit 16", self.broken(lambda m: self.item(m, "present_position").update(sign_bit=16)))
        self.assertIn("initial 2000 outside",
                      self.broken(lambda m: self.item(m, "maximum_torque").update(initial=2000)))
        self.assertIn("names no item", self.broken(lambda m: self.item(m, "torque_limit").update(initial_from="x")))
        self.assertIn("duplicate keys", self.broken(lambda m: self.item(m, "phase").update(key="id")))
        self.assertIn("Baud rate", self.broken(lambda m: m["baud_rates"].pop()))

    def test_a_model_number_the_library_has_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            catalog = Path(d) / "catalog.json"
            catalog.write_text('{"models": [{"name": "rx-10", "model_number": 10}]}', encoding="utf-8")
            check_model_numbers([{"name": "a", "model_number": 11}], catalog)
            with self.assertRaisesRegex(ValueError, "a and rx-10 both report model number 10"):
                check_model_numbers([{"name": "a", "model_number": 10}], catalog)


if __name__ == "__main__":
    unittest.main()
