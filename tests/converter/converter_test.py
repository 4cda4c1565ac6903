"""Unit tests of the model converter (scripts/model_converter): the Markdown and page parsing, the
Range cells and range arithmetic, the order in which an item's range is decided, and the
decision tables' coverage of every family. Standard library only; pages are written into a
temporary reference directory, so ../shared/reference is not needed."""
import sys
import tempfile
import textwrap
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "scripts"))

import json  # noqa: E402

from unittest import mock  # noqa: E402

from model_converter import builder, firmware, item_builder, item_ranges, modbus_map  # noqa: E402
from model_converter.decisions import catalogue, item_rules, model_fields, modbus, motor_specs  # noqa: E402
from model_converter.items import Draft  # noqa: E402
from model_converter.markdown import (camel_to_include, clean_cell, clean_unit, parse_bps, parse_int,  # noqa: E402
                                      select_liquid_branch, snake_key, tables_in, unit_number)
from model_converter.page import description_sections, expand_ellipses, map_columns, read_page  # noqa: E402
from model_converter.decisions.catalogue import CONVERTED_PAGES, classify, lineage  # noqa: E402
from model_converter.ranges import bound_keys, evidence_found, find_choice, full_width, parse_range, rc  # noqa: E402
from model_converter.reference import Reference  # noqa: E402
from model_converter.spec_table import parse_spec_table  # noqa: E402

HEADER = ("| Address | Size(Byte) | Data Name | Access | Initial Value | Range | Unit |\n"
          "|---|---|---|---|---|---|---|\n")


def page_text(eeprom: str, ram: str, descriptions: str = "") -> str:
    """A control-table page in the reference's layout."""
    return (f"# TEST-1 — control table\n\n## Control Table of EEPROM Area\n\n{HEADER}{textwrap.dedent(eeprom)}\n"
            f"## Control Table of RAM Area\n\n{HEADER}{textwrap.dedent(ram)}\n"
            f"## Control Table Description\n\n{textwrap.dedent(descriptions)}")


class TempReference:
    """A reference directory with the given pages and includes, and a models.tsv naming them."""

    def __init__(self, pages: dict, includes: dict | None = None):
        self.dir = tempfile.TemporaryDirectory()
        root = Path(self.dir.name)
        (root / "control-tables" / "includes").mkdir(parents=True)
        for name, text in pages.items():
            (root / "control-tables" / f"{name}.md").write_text(text, encoding="utf-8")
        for name, text in (includes or {}).items():
            (root / "control-tables" / "includes" / f"{name}.md").write_text(text, encoding="utf-8")
        rows = "".join(f"{n}\t{n}.md\n" for n in pages)
        (root / "models.tsv").write_text("model\tcontrol_table_file\n" + rows, encoding="utf-8")
        self.ref = Reference(root)

    def close(self):
        self.dir.cleanup()


class MarkdownTest(unittest.TestCase):
    def test_a_cell_loses_links_html_entities_emphasis_and_escapes(self):
        self.assertEqual(clean_cell(" [Goal Position](#goal-position) "), "Goal Position")
        self.assertEqual(clean_cell("**1**<br>2"), "1 2")
        self.assertEqual(clean_cell("rev/min<sup>2</sup>"), "rev/min²")
        self.assertEqual(clean_cell("0.06&deg; 2\\~3 _Modbus_ `x`"), "0.06° 2~3 Modbus x")

    def test_numbers_take_thousands_separators_only_in_groups_of_three(self):
        self.assertEqual(parse_int("1,044,479"), 1044479)
        self.assertEqual(parse_int(" -501,923 "), -501923)
        self.assertEqual(parse_int("−5"), -5)
        self.assertEqual(parse_int("250"), 250)
        self.assertIsNone(parse_int("1,2"))
        self.assertIsNone(parse_int("Max Torque"))
        self.assertIsNone(parse_int("-"))

    def test_pipe_tables_are_found_between_text_with_clean_headers_and_raw_cells(self):
        lines = ["text", "| **Value** | Baud |", "|:---:|---|", "| 0 | [9,600](#x) |", "", "| a | b |",
                 "| -- | -- |", "| 1 | 2 |"]
        tabs = tables_in(lines)
        self.assertEqual([t.line for t in tabs], [1, 5])
        self.assertEqual(tabs[0].header, ["Value", "Baud"])
        self.assertEqual(tabs[0].rows, [[" 0 ", " [9,600](#x) "]])
        self.assertEqual(tables_in(lines, 0, 4)[0].rows, [[" 0 ", " [9,600](#x) "]])

    def test_keys_are_snake_case_without_parenthesised_parts(self):
        self.assertEqual(snake_key("Goal Position"), "goal_position")
        self.assertEqual(snake_key("Secondary(Shadow) ID"), "secondary_id")
        self.assertEqual(snake_key("Indirect Address 12"), "indirect_address_12")

    def test_include_tags_name_their_files(self):
        self.assertEqual(camel_to_include("ControlTableOpmodeSix2"), "control_table_opmode_six_2")

    def test_the_liquid_branch_of_the_product_group_is_kept(self):
        text = ("a{% if page.product_group=='xl330' %}X{% elsif page.product_group=='dxl_x430' %}Y"
                "{% else %}Z{% endif %}b{% if page.product_group!='xl330' %}N{% endif %}")
        self.assertEqual(select_liquid_branch(text, "xl330"), "aXb")
        self.assertEqual(select_liquid_branch(text, "dxl_x430"), "aYbN")
        self.assertEqual(select_liquid_branch(text, "dxl_mx"), "aZbN")

    def test_units_and_bit_rates_read_as_printed(self):
        self.assertEqual(clean_unit("about 0.229 [ rev/min ]"), "about 0.229 [rev/min]")
        self.assertIsNone(clean_unit(" - "))
        self.assertEqual(unit_number("about 0.229 [rev/min]"), 0.229)
        self.assertIsNone(unit_number("[pulse]"))
        self.assertEqual(parse_bps("57,600"), 57600)
        self.assertEqual(parse_bps("4.5M"), 4500000)
        self.assertEqual(parse_bps("1 Mbps"), 1000000)
        self.assertEqual(parse_bps("9,600 [bps]"), 9600)
        self.assertIsNone(parse_bps("reserved"))


def row(address, size, name, initial="0", access="RW", range_="-", area="RAM", unit="-"):
    """A read_rows() row as the page parser hands it to expand_ellipses."""
    return {"area": area, "address": str(address), "size": str(size), "name": name, "access": access,
            "initial": str(initial), "range": range_, "unit": unit, "min": "", "max": "", "has_minmax": False,
            "raw": f"| {address} | {name} |"}


ELLIPSIS = row("…", "…", "…", "…", "…")


class PageTest(unittest.TestCase):
    def test_columns_are_located_by_their_header_text(self):
        cols = map_columns(["Address", "Size (Byte)", "Data Name", "Access", "Initial Value", "Min", "Max"])
        self.assertEqual(cols, {"address": 0, "size": 1, "name": 2, "access": 3, "initial": 4, "min": 5, "max": 6})
        with self.assertRaisesRegex(ValueError, "lacks 'access'"):
            map_columns(["Address", "Size", "Data Name", "Initial Value"])

    def test_an_ellipsis_row_expands_to_the_series_it_stands_for(self):
        rows = expand_ellipses([row(168, 2, "Indirect Address 1", 224), row(170, 2, "Indirect Address 2", 225),
                                ELLIPSIS, row(176, 2, "Indirect Address 5", 228)])
        self.assertEqual([(r.address, r.name, r.initial, r.expanded) for r in rows],
                         [(168, "Indirect Address 1", "224", False), (170, "Indirect Address 2", "225", False),
                          (172, "Indirect Address 3", "226", True), (174, "Indirect Address 4", "227", True),
                          (176, "Indirect Address 5", "228", False)])

    def test_an_ellipsis_the_next_row_does_not_continue_is_refused(self):
        with self.assertRaisesRegex(ValueError, "address series does not reach 178"):
            expand_ellipses([row(168, 2, "Indirect Address 1"), row(170, 2, "Indirect Address 2"), ELLIPSIS,
                             row(178, 2, "Indirect Address 5")])
        with self.assertRaisesRegex(ValueError, "initial series"):
            expand_ellipses([row(224, 1, "Indirect Data 1", 0), row(225, 1, "Indirect Data 2", 1), ELLIPSIS,
                             row(228, 1, "Indirect Data 5", 9)])
        with self.assertRaisesRegex(ValueError, "cannot expand"):
            expand_ellipses([row(224, 1, "LED"), row(225, 1, "Indirect Data 2"), ELLIPSIS,
                             row(228, 1, "Indirect Data 5")])

    def test_description_sections_name_the_addresses_of_their_heading(self):
        lines = ["## Control Table Description", "### [Goal Position](#x)(116)", "text", "### Indirect Data(224, 225)",
                 "more"]
        secs = description_sections(lines)
        self.assertEqual([(s.title, s.addresses, s.start, s.end) for s in secs],
                         [("Goal Position(116)", [116], 2, 3), ("Indirect Data(224, 225)", [224, 225], 4, 5)])

    def test_a_page_is_its_two_tables_and_its_sections_with_includes_expanded(self):
        text = page_text("| 0 | 2 | [Model Number](#m) | R | 1,200 | - | - |\n",
                         "| 64 | 1 | Torque Enable | RW | 0 | 0 ~ 1 | - |\n",
                         "### Torque Enable(64)\n<ControlTableTorqueEnable />\n")
        include = "{% if page.product_group=='xl330' %}XL330 text{% else %}other text{% endif %}"
        tmp = TempReference({"test-1": text}, {"control_table_torque_enable": include})
        self.addCleanup(tmp.close)
        page = read_page(tmp.ref, "test-1", "x", "xl330")
        self.assertEqual([(r.address, r.size, r.name, r.access, r.initial, r.area) for r in page.rows],
                         [(0, 2, "Model Number", "R", "1,200", "EEPROM"), (64, 1, "Torque Enable", "RW", "0", "RAM")])
        self.assertIn("range", page.columns)
        (sec,) = page.section_for(64)
        self.assertEqual(page.section_text(sec, tmp.ref).strip(), "XL330 text")

    def test_a_page_without_an_eeprom_and_a_ram_table_is_refused(self):
        ram_only = "## Control Table of RAM Area\n\n" + HEADER + "| 64 | 1 | LED | RW | 0 | - | - |\n"
        tmp = TempReference({"test-1": ram_only})
        self.addCleanup(tmp.close)
        with self.assertRaisesRegex(ValueError, "expected an EEPROM and a RAM table"):
            read_page(tmp.ref, "test-1", "x", "dxl_x430")

    def test_a_combined_table_is_split_by_its_area_column_and_reads_the_protocol_2_values(self):
        combined = ("## Control Table Configuration\n\n"
                    "| Address | Size(Byte) | _Modbus_<br>Address | Area | Data Name | Access | Initial<br>Value | "
                    "Range | Unit |\n|---|---|---|---|---|---|---|---|---|\n"
                    "| 0 | 2 | 40001 | EEPROM | [Model Number](#m) | R | 4,040<br />4,041<sup>1)</sup> | "
                    "4,040 **(Dynamixel Protocol 2.0)**<br />4,041 **(Modbus)** | - |\n"
                    "| 11 | 1 | 40006 (Hi byte) | EEPROM | Protocol Type | RW | 2<br />10 | "
                    "2 **(Dynamixel Protocol 2.0)**<br />10 **(Modbus)** | - |\n"
                    "| 212 | 4 | 40107 | Hybrid | Velocity I Gain | RW | 100 | 0 ~ 2,147,483,647 | - |\n"
                    "| 512 | 1 | 40257 (Lo byte) | RAM | Torque Enable | RW | 0 | 0 ~ 1 | - |\n"
                    "| N/A | 2 | 41002 | RAM | Reboot Instruction | W | - | - | - |\n")
        tmp = TempReference({"test-1": combined})
        self.addCleanup(tmp.close)
        page = read_page(tmp.ref, "test-1", "y", "dxl_y_m")
        self.assertEqual([(r.address, r.name, r.initial, r.range, r.area) for r in page.rows],
                         [(0, "Model Number", "4,040", "-", "EEPROM"), (11, "Protocol Type", "2", "2, 10", "EEPROM"),
                          (212, "Velocity I Gain", "100", "0 ~ 2,147,483,647", "Hybrid"),
                          (512, "Torque Enable", "0", "0 ~ 1", "RAM")])
        self.assertEqual(page.rows[0].by_protocol, "4,040 4,0411)")
        self.assertEqual(page.modbus_only, ["Reboot Instruction"])

    def test_a_combined_table_with_an_unknown_area_is_refused(self):
        combined = ("## Control Table Configuration\n\n| Address | Size(Byte) | Area | Data Name | Access | "
                    "Initial Value |\n|---|---|---|---|---|---|\n| 0 | 2 | Flash | Model Number | R | 1 |\n")
        tmp = TempReference({"test-1": combined})
        self.addCleanup(tmp.close)
        with self.assertRaisesRegex(ValueError, "unknown area 'Flash'"):
            read_page(tmp.ref, "test-1", "y", "dxl_y_m")

    def test_the_specifications_table_gives_the_figures_at_the_recommended_voltage(self):
        lines = ["| Item | Specifications |", "|---|---|",
                 "| Input Voltage | 10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**) |",
                 "| Stall Torque | 3.8 [N.m] (at 11.1 [V], 2.1 [A])<br>**4.1 [N.m] (at 12.0 [V], 2.3 [A])** |",
                 "| No Load Speed | 43 [rev/min] (at 11.1 [V])<br>**46 [rev/min] (at 12.0 [V])** |"]
        spec = parse_spec_table(lines)
        self.assertEqual((spec.rpm, spec.nm, spec.amps, spec.volts), (46, 4.1, 2.3, 12.0))
        self.assertIn("recommended input voltage", spec.detail)
        self.assertIsNone(parse_spec_table(["| Item | Specifications |", "|---|---|", "| Weight | 82 [g] |"]))


class RangeCellTest(unittest.TestCase):
    def test_a_numeric_range(self):
        spec = parse_range(" 0 ~ 4,095 ")
        self.assertEqual((spec.min, spec.max, spec.values, spec.raw), (0, 4095, None, "0 ~ 4,095"))

    def test_no_range(self):
        for cell in ("", "-", "…", " ... "):
            self.assertIsNone(parse_range(cell))

    def test_a_bound_may_carry_its_other_name_in_brackets(self):
        spec = parse_range("- Voltage(PWM)Limit(64) ~ <br />Voltage(PWM) Limit(64)")
        self.assertEqual((spec.lo_ref, spec.hi_ref), ((True, "Voltage(PWM)Limit", 64), (False, "Voltage(PWM) Limit", 64)))
        self.assertIn("pwm_limit", bound_keys(spec.lo_ref[1]))
        self.assertIn("pwm_limit", bound_keys(spec.hi_ref[1]))
        self.assertNotIn("current_limit", bound_keys("Voltage(PWM) Limit"))

    def test_bounds_named_by_other_items(self):
        spec = parse_range("[Min Position Limit(52)](#x) ~ Max Position Limit(48)")
        self.assertEqual((spec.min, spec.max), (None, None))
        self.assertEqual(spec.lo_ref, (False, "Min Position Limit", 52))
        self.assertEqual(spec.hi_ref, (False, "Max Position Limit", 48))
        spec = parse_range("-PWM Limit(36) ~ PWM Limit(36)")
        self.assertEqual(spec.lo_ref, (True, "PWM Limit", 36))

    def test_a_number_on_one_side_and_a_bound_on_the_other(self):
        spec = parse_range("0 ~ Velocity Limit(44)")
        self.assertEqual((spec.min, spec.hi_ref), (0, (False, "Velocity Limit", 44)))

    def test_two_ranges_in_one_cell_keep_the_first_and_the_rest_as_extra(self):
        spec = parse_range("0 ~ 32,767<br>0 ~ 32,737")
        self.assertEqual((spec.min, spec.max, spec.extra), (0, 32767, [(0, 32737)]))
        spec = parse_range("0 ~ 252 (DYNAMIXEL Protocol 2.0)<br>1 ~ 247 (Modbus)")
        self.assertEqual((spec.min, spec.max, spec.extra), (0, 252, [(1, 247)]))

    def test_a_list_of_values_and_a_lone_number(self):
        self.assertEqual(parse_range("0, 1, 3, 4, 16").values, [0, 1, 3, 4, 16])
        spec = parse_range("3")
        self.assertEqual((spec.values, spec.min), ([3], None))

    def test_a_cell_that_is_not_a_range_is_refused(self):
        for cell in ("see below", "0 ~ lots"):
            with self.assertRaisesRegex(ValueError, "not understood"):
                parse_range(cell)


class RangeArithmeticTest(unittest.TestCase):
    def test_a_list_of_mask_bits_is_any_combination_of_them(self):
        spec = parse_range("0x20(Overload)<br /> 0x10(Electrical Shock)<br /> 0x01(Input Voltagae)")
        self.assertEqual((spec.min, spec.max), (0, 0x31))

    def test_full_width_of_each_size(self):
        self.assertEqual(full_width(1, False), (0, 255))
        self.assertEqual(full_width(2, True), (-32768, 32767))
        self.assertEqual(full_width(4, False), (0, 4294967295))
        self.assertEqual(full_width(4, True), (-2147483648, 2147483647))

    def test_a_range_choice_is_found_by_family_and_key_first_match_first(self):
        choices = [rc("ax rx", ("cw_angle_limit", "ccw_angle_limit"), 0, 1023, "PAGE", "same as Goal Position"),
                   rc("ax ex", "cw_angle_limit", 0, 4095, "PAGE")]
        self.assertEqual(find_choice(choices, ("ax",), "cw_angle_limit").max, 1023)
        self.assertEqual(find_choice(choices, ("ex",), "cw_angle_limit").max, 4095)
        self.assertEqual(choices[0].quotes, ("same as Goal Position",))
        self.assertIsNone(find_choice(choices, ("mx1",), "cw_angle_limit"))

    def test_a_range_choice_falls_back_along_the_lineage(self):
        choices = [rc("rx", "baud_rate", 0, 254, "PAGE"), rc("dx", "id", 0, 253, "PAGE")]
        self.assertEqual(find_choice(choices, ("dx", "rx"), "baud_rate").max, 254)
        self.assertEqual(find_choice(choices, ("dx", "rx"), "id").max, 253)
        self.assertIsNone(find_choice(choices, ("rx",), "id"))

    def test_lineage_is_variant_family_then_parents(self):
        self.assertEqual(lineage("x", "xl330"), ("x330", "x"))
        self.assertEqual(lineage("x", "dxl_x430"), ("x",))
        self.assertEqual(lineage("dx", "dxl_dx"), ("dx", "rx"))
        self.assertEqual(lineage("pro_a", "dxl_pro_a"), ("pro_a", "p"))

    def test_range_evidence_must_hold_a_quote_whitespace_normalised(self):
        files = {"control-tables/includes/a.md": "The range\nof the   value is 0~255."}
        on_file = rc("ax", "k", 0, 255, "control-tables/includes/a.md", ("nothing", "range of the value is 0~255"))
        self.assertTrue(evidence_found(on_file, "", files.get))
        self.assertFalse(evidence_found(rc("ax", "k", 0, 1, "control-tables/includes/a.md", "0~254"), "", files.get))
        self.assertTrue(evidence_found(rc("ax", "k", 0, 1, "PAGE", "on  this page"), "on this\npage", files.get))
        self.assertTrue(evidence_found(rc("ax", "k", 0, 1, "https://example.org/x.md"), "", files.get))


class ItemRangeOrderTest(unittest.TestCase):
    """Where an item's range comes from: the table, its description section, a choice, a donor page,
    else the full width; then bounds named by other items."""

    def draft(self, eeprom, ram, descriptions=""):
        """An X-family page with a Range column, its items made and their ranges filled in."""
        tmp = TempReference({"test-1": page_text(eeprom, ram, descriptions)})
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "x", "dxl_x430"), {})
        item_builder.make_items(d)
        item_ranges.printed_ranges(d)
        item_ranges.fill_unprinted_ranges(d)
        return d

    def test_the_table_then_the_description_section_then_the_full_width(self):
        d = self.draft("| 7 | 1 | ID | RW | 1 | 0 ~ 252 | - |\n",
                       "| 64 | 1 | Torque Enable | RW | 0 | - | - |\n| 65 | 1 | LED | RW | 0 | - | - |\n",
                       "### Torque Enable(64)\n| Unit | Value Range |\n|---|---|\n| - | 0 ~ 1 |\n")
        by_key = d.by_key
        self.assertEqual((by_key["id"].min, by_key["id"].max, by_key["id"].range_from), (0, 252, "table"))
        self.assertEqual((by_key["torque_enable"].max, by_key["torque_enable"].range_from), (1, "description"))
        self.assertIn("description section 'Torque Enable(64)'", by_key["torque_enable"].notes[0])
        self.assertEqual((by_key["led"].min, by_key["led"].range_from), (None, "default"))
        self.assertIn("full width", by_key["led"].notes[0])

    def test_a_page_without_a_range_column_takes_a_documented_choice_with_its_evidence(self):
        header = "| Address | Size(Byte) | Data Name | Access | Initial Value |\n|---|---|---|---|---|\n"
        text = (f"## Control Table of EEPROM Area\n\n{header}| 3 | 1 | ID | RW | 1 |\n\n"
                f"## Control Table of RAM Area\n\n{header}| 24 | 1 | Torque Enable | RW | 0 |\n")
        tmp = TempReference({"test-1": text},
                            {"control_table_id": "0~253 (0xFD) values can be used as an ID",
                             "ax-legacy-page-description-sections": "|1|Generates Torque by impressing|"})
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "ax", "dxl_ax"), {})
        item_builder.make_items(d)
        item_ranges.printed_ranges(d)
        item_ranges.fill_unprinted_ranges(d)
        item = d.by_key["id"]
        self.assertEqual((item.min, item.max, item.range_from), (0, 253, "choice"))
        self.assertIn("'0~253 (0xFD) values can be used as an ID'", item.notes[0])

    def test_evidence_that_is_not_where_the_choice_says_stops_the_conversion(self):
        header = "| Address | Size(Byte) | Data Name | Access | Initial Value |\n|---|---|---|---|---|\n"
        text = (f"## Control Table of EEPROM Area\n\n{header}| 3 | 1 | ID | RW | 1 |\n\n"
                f"## Control Table of RAM Area\n\n{header}| 25 | 1 | LED | RW | 0 |\n")
        tmp = TempReference({"test-1": text}, {"control_table_id": "some other text"})
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "ax", "dxl_ax"), {})
        item_builder.make_items(d)
        with self.assertRaisesRegex(SystemExit, "test-1.id: evidence"):
            item_ranges.fill_unprinted_ranges(d)

    def test_a_donor_page_lends_the_range_of_the_same_item(self):
        header = "| Address | Size(Byte) | Data Name | Access | Initial Value |\n|---|---|---|---|---|\n"
        text = (f"## Control Table of EEPROM Area\n\n{header}| 13 | 1 | Protocol Version | RW | 2 |\n\n"
                f"## Control Table of RAM Area\n\n{header}| 64 | 1 | Torque Enable | RW | 0 |\n")
        donor = page_text("| 13 | 1 | Protocol Type | RW | 2 | 1 ~ 2 | - |\n",
                          "| 64 | 1 | Torque Enable | RW | 0 | 0 ~ 1 | - |\n")
        tmp = TempReference({"test-1": text, "donor-1": donor})
        self.addCleanup(tmp.close)
        donors = {"donor-1": read_page(tmp.ref, "donor-1", "x", "dxl_x430")}
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "mx2", "dxl_mx2"), donors)
        item_builder.make_items(d)
        item_ranges.printed_ranges(d)
        item_ranges.fill_unprinted_ranges(d)
        for key, hi in (("protocol_version", 2), ("torque_enable", 1)):
            item = d.by_key[key]
            self.assertEqual((item.max, item.range_from), (hi, "donor"), key)
            self.assertIn("control-tables/donor-1.md", item.notes[0])

    def test_bounds_named_by_other_items_take_their_static_range(self):
        d = self.draft("| 36 | 2 | PWM Limit | RW | 885 | 0 ~ 885 | - |\n"
                       "| 48 | 4 | Max Position Limit | RW | 4,095 | 0 ~ 4,095 | - |\n"
                       "| 52 | 4 | Min Position Limit | RW | 0 | 0 ~ 4,095 | - |\n",
                       "| 100 | 2 | Goal PWM | RW | - | -PWM Limit(36) ~ PWM Limit(36) | - |\n"
                       "| 116 | 4 | Goal Position | RW | - | Min Position Limit(52) ~ Max Position Limit(48) | - |\n")
        item_ranges.resolve_limits(d)
        pwm, pos = d.by_key["goal_pwm"], d.by_key["goal_position"]
        self.assertEqual((pwm.limit_min, pwm.limit_max, pwm.min, pwm.max, pwm.signed),
                         ("-pwm_limit", "pwm_limit", -885, 885, True))
        self.assertEqual((pos.limit_min, pos.limit_max, pos.min, pos.max),
                         ("min_position_limit", "max_position_limit", 0, 4095))

    def test_a_printed_range_that_excludes_the_factory_value_is_widened_to_it(self):
        d = self.draft("| 12 | 1 | Secondary(Shadow) ID | RW | 255 | 0 ~ 252 | - |\n",
                       "| 64 | 1 | Torque Enable | RW | 0 | 0 ~ 1 | - |\n")
        item_builder.initial_values(d, 45)
        item_ranges.widen_to_factory(d)
        item = d.by_key["secondary_id"]
        self.assertEqual((item.min, item.max), (0, 255))
        self.assertIn("0 ~ 252 is printed but the factory value is 255", item.notes[-1])
        self.assertEqual(d.by_key["torque_enable"].max, 1)

    def test_a_bound_that_names_no_item_is_refused(self):
        with self.assertRaisesRegex(ValueError, "which is not an item"):
            self.draft("| 36 | 2 | PWM Limit | RW | 885 | 0 ~ 885 | - |\n",
                       "| 100 | 2 | Goal PWM | RW | - | -PWM Limit(38) ~ PWM Limit(36) | - |\n")


MODBUS_HEADER = ("| Address | Size(Byte) | _Modbus_<br>Address | Data Name | Access | Initial<br />Value | Range | Unit |\n"
                 "|---|---|---|---|---|---|---|---|\n")


class ModbusMapTest(unittest.TestCase):
    """A DYNAMIXEL-P page's Modbus Address column: checked against 40001 + floor(address / 2), its
    'N/A' rows (elided ones too) absent in Modbus, a misprint refused unless it is a named erratum."""

    EEPROM = ("| 0 | 2 | _40001_ | Model Number | R | 2,020 | - | - |\n"
              "| 7 | 1 | _40004 (Hi Byte)_ | ID | RW | 1 | 0 ~ 252 (**DYNAMIXEL Protocol 2.0**) <br /> 1 ~ 247 (**Modbus**) | - |\n"
              "| 8 | 1 | _40005 (Lo Byte)_ | Baud Rate | RW | 1 | 0 ~ 9 | - |\n"
              "| 9 | 1 | N/A | Return Delay Time | RW | 250 | 0 ~ 254 | - |\n"
              "| 168 | 2 | N/A | Indirect Address 1 | RW | 634 | 512 ~ 1,023 | - |\n"
              "| 170 | 2 | N/A | Indirect Address 2 | RW | 635 | 512 ~ 1,023 | - |\n"
              "| ... | ... | ... | ... | ... | ... | ... | ... |\n"
              "| 176 | 2 | N/A | Indirect Address 5 | RW | 638 | 512 ~ 1,023 | - |\n")
    RAM = ("| 512 | 1 | *40257 (Lo Byte)* | Torque Enable | RW | 0 | 0 ~ 1 | - |\n"
           "| 564 | 4 | *40283* | Goal Position | RW | - | -1,000 ~ 1,000 | - |\n")

    def draft(self, eeprom=EEPROM, ram=RAM):
        """A P-family page with a Modbus column, its items made and their ranges filled in."""
        text = (f"## Control Table of EEPROM Area\n\n{MODBUS_HEADER}{eeprom}\n"
                f"## Control Table of RAM Area\n\n{MODBUS_HEADER}{ram}\n")
        tmp = TempReference({"test-1": text})
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "p", "dxl_p"), {})
        item_builder.make_items(d)
        item_ranges.printed_ranges(d)
        return d

    def test_the_rule_gives_the_register_and_for_one_byte_items_the_byte(self):
        self.assertEqual(modbus_map.expected_cell(0, 2), "40001")
        self.assertEqual(modbus_map.expected_cell(7, 1), "40004 (Hi Byte)")
        self.assertEqual(modbus_map.expected_cell(512, 1), "40257 (Lo Byte)")
        self.assertEqual(modbus_map.expected_cell(564, 4), "40283")
        with self.assertRaisesRegex(ValueError, "straddles two registers"):
            modbus_map.expected_cell(9, 2)

    def test_rows_printed_na_and_their_elided_series_are_absent_in_modbus(self):
        d = self.draft()
        modbus_map.read_modbus_map(d, 45, [])
        absent = [i.key for i in d.items if i.absent_in]
        self.assertEqual(absent, ["return_delay_time"] + [f"indirect_address_{n}" for n in range(1, 6)])
        self.assertEqual(d.by_key["return_delay_time"].to_json()["absent_in"], ["modbus"])
        self.assertNotIn("absent_in", d.by_key["goal_position"].to_json())
        self.assertIn("firmware_version 45", d.notes[0])
        self.assertIn("Return Delay Time(9), Indirect Address 1 ~ 5(168 ~ 176)", d.notes[1])

    def test_the_id_keeps_the_protocol_2_range_and_notes_the_modbus_one(self):
        note = self.draft().by_key["id"].notes[0]
        self.assertIn("the Modbus range is enforced by the protocol (ID 1 ~ 247 over Modbus", note)
        self.assertEqual((self.draft().by_key["id"].min, self.draft().by_key["id"].max), (0, 252))

    def test_a_misprinted_address_refuses_the_page_naming_the_row(self):
        d = self.draft(self.EEPROM.replace("_40005 (Lo Byte)_", "_40006 (Lo Byte)_"))
        with self.assertRaisesRegex(ValueError, r"row Baud Rate\(8\): Modbus Address '40006 \(Lo Byte\)' is not "
                                                r"'40005 \(Lo Byte\)'"):
            modbus_map.read_modbus_map(d, 45, [])
        d = self.draft(self.EEPROM.replace("_40004 (Hi Byte)_", "_40004 (Lo Byte)_"))
        with self.assertRaisesRegex(ValueError, r"row ID\(7\)"):
            modbus_map.read_modbus_map(d, 45, [])
        d = self.draft(ram=self.RAM.replace("*40283*", "*40283 (Lo Byte)*"))
        with self.assertRaisesRegex(ValueError, r"row Goal Position\(564\)"):
            modbus_map.read_modbus_map(d, 45, [])

    def test_a_named_erratum_is_noted_and_one_the_page_does_not_need_is_refused(self):
        misprint = {"test-1": {8: ("40006 (Lo Byte)", "why")}}
        with mock.patch.dict(modbus_map.MODBUS_ERRATA, misprint):
            d = self.draft(self.EEPROM.replace("_40005 (Lo Byte)_", "_40006 (Lo Byte)_"))
            modbus_map.read_modbus_map(d, 45, [])
            self.assertIn("modbus: the page prints '40006 (Lo Byte)'; the map places the item at '40005 (Lo Byte)': "
                          "why", d.by_key["baud_rate"].notes)
            with self.assertRaisesRegex(ValueError, r"names rows at \[8\] as misprinted"):
                modbus_map.read_modbus_map(self.draft(), 45, [])

    def test_an_elided_series_between_mapped_rows_has_no_address_and_is_refused(self):
        eeprom = ("| 56 | 1 | _40029 (Lo Byte)_ | External Port Mode 1 | RW | 3 | 0 ~ 3 | - |\n"
                  "| 57 | 1 | _40029 (Hi Byte)_ | External Port Mode 2 | RW | 3 | 0 ~ 3 | - |\n"
                  "| ... | ... | ... | ... | ... | ... | ... | ... |\n"
                  "| 59 | 1 | _40030 (Hi Byte)_ | External Port Mode 4 | RW | 3 | 0 ~ 3 | - |\n")
        d = self.draft(self.EEPROM + eeprom)
        with self.assertRaisesRegex(ValueError, r"row External Port Mode 3\(58\) has no Modbus address"):
            modbus_map.read_modbus_map(d, 45, [])

    def test_a_firmware_below_the_first_modbus_one_is_refused(self):
        with self.assertRaisesRegex(ValueError, "firmware 10 is below V11"):
            modbus_map.read_modbus_map(self.draft(), 10, [])
        with self.assertRaisesRegex(ValueError, "firmware 9 is below V11"):
            modbus_map.read_modbus_map(self.draft(), 45, [9])

    def test_a_page_without_a_modbus_column_is_refused(self):
        tmp = TempReference({"test-1": page_text("| 7 | 1 | ID | RW | 1 | 0 ~ 252 | - |\n",
                                                 "| 512 | 1 | Torque Enable | RW | 0 | 0 ~ 1 | - |\n")})
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "p", "dxl_p"), {})
        item_builder.make_items(d)
        with self.assertRaisesRegex(ValueError, "has no Modbus Address column"):
            modbus_map.read_modbus_map(d, 45, [])

    def test_the_models_that_list_modbus_are_the_p_pages_and_rh_p12_rna_each_with_a_firmware(self):
        speaking = set()
        for name in catalogue.CONVERTED_PAGES:
            family, group = catalogue.classify(name)
            keys = (name, *catalogue.lineage(family, group))
            listed = next(model_fields.PROTOCOLS[k] for k in keys if k in model_fields.PROTOCOLS)[0]
            if "modbus" in listed:
                speaking.add(name)
                self.assertTrue(any(k in modbus.MODBUS_FIRMWARE for k in keys), name)
        self.assertEqual(speaking, {"ph54-200-s500-r", "ph54-100-s500-r", "ph42-020-s300-r", "pm54-060-s250-r",
                                    "pm54-040-s250-r", "pm42-010-s260-r", "rh-p12-rna"})


class DecisionTablesTest(unittest.TestCase):
    """Adding a page or a family is data: every family and variant needs an entry in each table."""

    def test_page_names_give_family_product_group_and_variant(self):
        cases = {"xl-320": ("xl320", "dxl_xl320", "xl320"), "xl330-m288": ("x", "xl330", "x330"),
                 "xc330-t288": ("x", "xc330", "x330"), "2xl430-w250": ("x", "dxl_xl430", "x"), "xm540-w270": ("x", "dxl_x540", "x"),
                 "xm335-t323": ("x", "xm335", "x330"), "xw430-t200": ("x", "dxl_xw430", "x"),
                 "mx-28-2": ("mx2", "dxl_mx2", "mx2"), "mx-28": ("mx1", "dxl_mx", "mx1"),
                 "ex-106+": ("ex", "dxl_ex", "ex"), "ph54-200-s500-r": ("p", "dxl_p", "p"),
                 "h54-200-s500-r": ("pro", "dxl_pro", "pro"), "ym070-210-m001-rh": ("y", "dxl_y_m", "y"),
                 "ym080-230-b001-rh": ("y", "dxl_y_b", "y"), "ym070-210-r051-rh": ("y", "dxl_y_r", "y"),
                 "ym080-230-a099-rh": ("y", "dxl_y_a", "y")}
        for name, (family, group, variant) in cases.items():
            self.assertEqual(catalogue.classify(name), (family, group), name)
            self.assertEqual(catalogue.variant_of(family, group), variant, name)
        with self.assertRaisesRegex(SystemExit, "no family rule"):
            catalogue.classify("zz-1")

    def test_every_converted_page_has_a_family_rule(self):
        for name in catalogue.CONVERTED_PAGES:
            catalogue.classify(name)

    def test_every_family_and_variant_has_an_entry_in_each_per_family_table(self):
        tables = {"TIMING": model_fields.TIMING, "DEGREES_PER_PULSE": model_fields.DEGREES_PER_PULSE,
                  "MID_POSITION": item_rules.MID_POSITION, "FIRMWARE": model_fields.FIRMWARE,
                  "PROTOCOLS": model_fields.PROTOCOLS}
        for _, family, group in catalogue.PAGE_RULES:
            keys = catalogue.lineage(family, group)
            for table_name, table in tables.items():
                self.assertTrue(any(k in table for k in keys), f"{table_name} has none of {keys}")
        families = {family for _, family, _ in catalogue.PAGE_RULES}
        for table_name in ("TIMING", "DEGREES_PER_PULSE", "MID_POSITION"):
            self.assertLessEqual(set(tables[table_name]), families | set(catalogue.CONVERTED_PAGES),
                                 f"{table_name} names an unknown family or page")

    def test_every_initial_rule_sets_exactly_one_kind_of_value(self):
        for key, rule in item_rules.INITIAL_RULES.items():
            kinds = [rule.value is not None, bool(rule.copy_from), bool(rule.computed)]
            self.assertEqual(kinds.count(True), 1, key)
            if rule.computed:
                self.assertIn(rule.computed, item_builder.INITIAL_COMPUTATIONS, key)


def stated_number(value: float) -> str:
    """A pattern for value as a source may print it: 5675 as "5,675", 1.0 as "1", "1.0" or "1.00"."""
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    whole, _, fraction = text.partition(".")
    whole = whole if len(whole) <= 3 else f"{whole[:-3]},?{whole[-3:]}"
    fraction = rf"\.{fraction}0*" if fraction else r"(?:\.0+)?"
    return rf"(?<![\d.,]){whole}{fraction}(?!\d|\.\d)"


class MotorSpecsTest(unittest.TestCase):
    """Every motor figure taken from outside the reference is quoted in its source text."""

    def test_every_figure_and_voltage_appears_in_the_quoted_source(self):
        for name, spec in motor_specs.EXTERNAL_SPECS.items():
            for value in (spec.rpm, spec.nm, spec.amps, spec.volts):
                if value is not None:
                    self.assertGreater(value, 0, name)
                    self.assertRegex(spec.source, stated_number(value), name)

    def test_an_absent_figure_is_explained_and_a_stated_one_is_not_called_absent(self):
        fields = {"rpm": "no_load_speed_rpm", "nm": "stall_torque_nm", "amps": "stall_current_a"}
        for name, spec in motor_specs.EXTERNAL_SPECS.items():
            absent = [field for attr, field in fields.items() if getattr(spec, attr) is None]
            for field in absent:
                self.assertIn(field, spec.missing, name)
            if not absent:
                self.assertEqual(spec.missing, "", name)

    def test_keys_are_page_names(self):
        for name in motor_specs.EXTERNAL_SPECS:
            self.assertRegex(name, r"^[0-9a-z][0-9a-z+-]*$")

    def test_data_strings_give_their_numbers_as_printed(self):
        self.assertEqual(motor_specs.leading_number("5,675 [rev/min]"), 5675)
        self.assertIsInstance(motor_specs.leading_number("5,675 [rev/min]"), int)
        self.assertEqual(motor_specs.leading_number("16.0 [rev/min]"), 16.0)
        self.assertIsInstance(motor_specs.leading_number("16.0 [rev/min]"), float)
        self.assertRegex("0.60 [N.m] and 1.3 [A]", stated_number(0.6))
        self.assertNotRegex("1.3 [A]", stated_number(1.0))

    def test_continuous_only_models_quote_their_continuous_and_peak_figures(self):
        specs = motor_specs.continuous_only_specs()
        self.assertEqual(set(specs), set(motor_specs.CONTINUOUS_ONLY) | set(motor_specs.Y_PAGES))
        p_spec = specs["ph42-020-s300-r"]
        self.assertEqual((p_spec.rpm, p_spec.nm, p_spec.amps, p_spec.volts), (32.7, None, None, 24.0))
        self.assertIn("conttorque '5.1 [N.m]'", p_spec.missing)
        self.assertNotIn("peak", p_spec.missing)
        y_spec = specs["ym080-230-a099-rh"]
        self.assertEqual((y_spec.rpm, y_spec.volts), (32.2, 24.0))
        self.assertIn("maximumtorque '61.4 [N.m]'", y_spec.missing)


class FirmwareTest(unittest.TestCase):
    """What a page says about firmware: the versions its items need, and the older firmware whose
    Indirect blocks differ (firmware.py), against the model's firmware_version (builder.py)."""

    EEPROM = "| 6 | 1 | Firmware Version | R | - | - | - |\n"
    RAM = ("| 50 | 2 | Realtime Tick | R | - | 0 ~ 32,767 | - |\n"
           "| 168 | 2 | Indirect Address 1 | RW | 224 | 64 ~ 227 | - |\n"
           "| 224 | 1 | Indirect Data 1 | RW | 0 | 0 ~ 255 | - |\n")
    OLDER = ("**NOTE** : Firmware versions prior to V53 support up to 20 Indirect Address/Data items. The "
             "address range for Indirect Address is 168 ~ 207, and for Indirect Data is 208 ~ 227.\n\n")

    def draft(self, descriptions, group="xl330", includes=None, before=""):
        text = page_text(self.EEPROM, self.RAM, descriptions).replace("## Control Table Description",
                                                                      before + "## Control Table Description")
        tmp = TempReference({"test-1": text}, includes)
        self.addCleanup(tmp.close)
        d = Draft(tmp.ref, read_page(tmp.ref, "test-1", "x", group), {})
        item_builder.make_items(d)
        return d

    def test_an_item_documented_from_a_firmware_needs_that_firmware(self):
        d = self.draft("### Realtime-Tick (50)\ntext\n\n**NOTE** : This feature is available from Firmware v41.\n")
        (need,) = firmware.firmware_needs(d.ref, d.page)
        self.assertEqual((need.version, need.section, need.addresses), (41, "Realtime-Tick (50)", (50,)))
        self.assertIn("available from Firmware v41", need.quote)
        with self.assertRaisesRegex(ValueError, r"firmware_version 40 is below v41, which Realtime-Tick \(50\) needs"):
            builder.check_firmware(d, 40)
        builder.check_firmware(d, 41)

    def test_include_versions_follow_the_product_group_at_every_level_and_table_rows_name_others(self):
        include = ('{% if page.product_group == \'xl330\' %}{% assign v = "firmware **V46**" %}{% else %}'
                   '{% assign v = "firmware **V45**" %}{% endif %}\nTick is available from {{ v }}.\n'
                   "{% if page.product_group=='dxl_x430' %}a{% else %}b {% if page.product_group=='xl330' %}"
                   "{% else %}(**Firmware v49 or above**){% endif %}{% endif %}\n"
                   "| 2 | Protocol 2.0 | MX with Firmware v39 or above |\n")
        descriptions = "### Realtime-Tick (50)\n<ControlTableRealtimeTick />\n"
        needs = firmware.firmware_needs(*(lambda d: (d.ref, d.page))(
            self.draft(descriptions, "xl330", {"control_table_realtime_tick": include})))
        self.assertEqual([n.version for n in needs], [46])
        needs = firmware.firmware_needs(*(lambda d: (d.ref, d.page))(
            self.draft(descriptions, "xc330", {"control_table_realtime_tick": include})))
        self.assertEqual([n.version for n in needs], [45, 49])

    def test_a_need_of_an_item_the_model_lacks_does_not_count(self):
        d = self.draft("### Bus Watchdog(98)\nBus Watchdog (98) is available from firmware v60.\n")
        builder.check_firmware(d, 1)

    def test_the_older_indirect_note_becomes_a_variant_and_raises_the_default(self):
        d = self.draft("", before=self.OLDER)
        older = firmware.older_indirect(d.page)
        self.assertEqual((older.before, older.count, older.address, older.data), (53, 20, 168, 208))
        (variant,) = builder.firmware_variants(d, 53)
        self.assertEqual(variant["firmware_version"], 52)
        self.assertEqual(variant["indirect"], [{"address": 168, "data": 208, "count": 20}])
        self.assertIn("Firmware versions prior to V53 support up to 20", variant["notes"][0])
        with self.assertRaisesRegex(ValueError, "firmware_version 46 serves the Indirect blocks of V53 or later"):
            builder.firmware_variants(d, 46)
        self.assertIsNone(builder.firmware_variants(self.draft(""), 46))

    def test_an_older_indirect_note_whose_ranges_do_not_hold_its_count_is_refused(self):
        d = self.draft("", before=self.OLDER.replace("208 ~ 227", "208 ~ 230"))
        with self.assertRaisesRegex(ValueError, "do not hold 20 items"):
            firmware.older_indirect(d.page)


REFERENCE = ROOT.parent / "shared" / "reference"


class ShippedFirmwareTest(unittest.TestCase):
    """Every shipped model's firmware against its page: no item is served by a firmware older than
    the page says it needs, and the X330 pages' older Indirect layout is a variant. Fails, saying
    so, without ../shared/reference beside the checkout, as the other reference checks do."""

    def setUp(self):
        if not (REFERENCE / "control-tables").is_dir():
            self.fail(f"no {REFERENCE}/control-tables: ../shared/reference must be beside the checkout")

    def test_no_model_reports_a_firmware_below_what_its_page_requires_for_an_item_it_has(self):
        ref = Reference(REFERENCE)
        for name in CONVERTED_PAGES:
            with self.subTest(name):
                model = json.loads((ROOT / "models" / f"{name}.json").read_text(encoding="utf-8"))
                page = read_page(ref, name, *classify(name))
                addresses = {i["address"] for i in model["items"]}
                versions = [model["firmware_version"]] + [v["firmware_version"]
                                                          for v in model.get("firmware_variants", [])]
                needs = [(n, addresses) for n in firmware.firmware_needs(ref, page)]
                if name in item_rules.BORROWED_ROWS:  # a borrowed row brings its donor page's note along
                    donor_name, rows = item_rules.BORROWED_ROWS[name]
                    donor = read_page(ref, donor_name, *classify(donor_name))
                    borrowed = {r.address for r in donor.rows if r.name in rows}
                    needs += [(n, borrowed) for n in firmware.firmware_needs(ref, donor)]
                for need, served in needs:
                    if served & set(need.addresses):
                        for version in versions:
                            self.assertGreaterEqual(version, need.version,
                                                    f"{name} firmware {version}: {need.section}: '{need.quote}'")
                older = firmware.older_indirect(page)
                if older:
                    self.assertGreaterEqual(model["firmware_version"], older.before, older.quote)
                    self.assertEqual([v["firmware_version"] for v in model["firmware_variants"]], [older.before - 1])
                else:
                    self.assertNotIn("firmware_variants", model)

    def test_the_pages_with_the_v53_note_are_the_xl330_and_xc330_pages_and_not_xm335(self):
        ref = Reference(REFERENCE)
        with_note = [n for n in CONVERTED_PAGES if firmware.older_indirect(read_page(ref, n, *classify(n)))]
        self.assertEqual(with_note, ["xc330-m181", "xc330-m288", "xc330-t181", "xc330-t288", "xl330-m077",
                                     "xl330-m288"])


if __name__ == "__main__":
    unittest.main()
