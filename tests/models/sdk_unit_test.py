"""Unit tests of the SDK cross-check (ctest models.sdk_control_tables_unit): reading the SDK's
files, model views and firmware variants, the name mapping, the pairing rules, the comparison
and the explaining notes, and the whole run, on small texts written here (the reference is not
needed). Standard library only."""
import io
import json
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import sdk_control_tables_test as runner  # noqa: E402
from model_views import indirect_items, model_from_json  # noqa: E402
from sdk_compare import check, compare  # noqa: E402
from sdk_names import find, folded, spelled  # noqa: E402
from sdk_notes import parse_note  # noqa: E402
from sdk_pairing import Comparison, pair, select_file  # noqa: E402
from sdk_tables import firmware_limit, parse_model_file, parse_registry  # noqa: E402


def sdk_text(rows) -> str:
    """A `.model` file with the given (address, size, name) rows, in the SDK's layout."""
    table = "".join(f"{a}\t{s}\t{n}\n" for a, s, n in rows)
    return ("[type info]\nname\tvalue\nvalue_of_zero_radian_position\t2048\n\n"
            "[unit info]\nData Name\tvalue\tunit\tSign Type\nPresent Velocity\t0.229\trpm\tsigned\n\n"
            f"[control table]\nAddress\tSize\tData Name\n{table}")


def sdk_file(name, rows):
    return parse_model_file(sdk_text(rows), name)


def item(name, address, size, key=None):
    key = key or name.lower().replace(" ", "_").replace("(", "").replace(")", "")
    return {"key": key, "name": name, "address": address, "size": size}


def model_doc(name, number, items, firmware=45, notes=None, variants=None):
    doc = {"name": name, "model_number": number, "firmware_version": firmware, "items": items}
    if notes is not None:
        doc["notes"] = notes
    if variants is not None:
        doc["firmware_variants"] = variants
    return doc


def model(name, number, items, **kw):
    return model_from_json(model_doc(name, number, items, **kw), f"{name}.json")


BASIC_ROWS = [(0, 2, "Model Number"), (6, 1, "Firmware Version"), (7, 1, "ID")]
BASIC_ITEMS = [item("Model Number", 0, 2), item("Firmware Version", 6, 1), item("ID", 7, 1)]

# An XL330-like table: 8 indirect slots in one block (the SDK's Read alias is slot 4).
X330_INDIRECT = [{"address": 168, "data": 224, "count": 8}]
FW52_INDIRECT = [{"address": 168, "data": 200, "count": 4}]
X330_ROWS = BASIC_ROWS + [(168, 2, "Indirect Address 1"), (224, 1, "Indirect Data 1"),
                          (168, 2, "Indirect Address Write"), (224, 1, "Indirect Data Write"),
                          (174, 2, "Indirect Address Read"), (227, 1, "Indirect Data Read")]
FW52_ROWS = BASIC_ROWS + [(168, 2, "Indirect Address 1"), (200, 1, "Indirect Data 1"),
                          (168, 2, "Indirect Address Write"), (200, 1, "Indirect Data Write"),
                          (174, 2, "Indirect Address Read"), (203, 1, "Indirect Data Read")]


def x330_items():
    return BASIC_ITEMS + [{"key": i.key, "name": i.name, "address": i.address, "size": i.size}
                          for i in indirect_items(X330_INDIRECT, "test")]


class SdkTablesTest(unittest.TestCase):
    def test_the_registry_maps_files_to_numbers(self):
        self.assertEqual(parse_registry("Number\tName\n30\tmx_28.model\n1200\txl330_m288.model\n"),
                         {"mx_28.model": 30, "xl330_m288.model": 1200})

    def test_the_registry_refuses_a_bad_header_line_or_repetition(self):
        with self.assertRaisesRegex(ValueError, "dynamixel.model:1: expected the header"):
            parse_registry("Name\tNumber\n")
        with self.assertRaisesRegex(ValueError, r"dynamixel.model:3: expected '<model number>"):
            parse_registry("Number\tName\n30\tmx_28.model\n31 mx_64.model\n")
        with self.assertRaisesRegex(ValueError, "30 is listed twice"):
            parse_registry("Number\tName\n30\tmx_28.model\n30\tmx_64.model\n")
        with self.assertRaisesRegex(ValueError, "mx_28.model is listed twice"):
            parse_registry("Number\tName\n30\tmx_28.model\n31\tmx_28.model\n")

    def test_a_model_file_yields_its_control_table_rows_only(self):
        f = sdk_file("xl330_m288.model", BASIC_ROWS)
        self.assertEqual([(i.address, i.size, i.name, i.line) for i in f.items],
                         [(0, 2, "Model Number", 11), (6, 1, "Firmware Version", 12), (7, 1, "ID", 13)])
        self.assertEqual((f.base_file, f.last_firmware), ("xl330_m288.model", None))

    def test_the_fw_suffix_names_the_last_firmware_of_the_table(self):
        self.assertEqual(firmware_limit("xl330_m288_fw52.model"), ("xl330_m288.model", 52))
        self.assertEqual(firmware_limit("xw430_t200.model"), ("xw430_t200.model", None))
        f = sdk_file("xc330_t181_fw52.model", BASIC_ROWS)
        self.assertEqual((f.base_file, f.last_firmware), ("xc330_t181.model", 52))

    def test_a_model_file_with_a_bad_row_is_refused_with_its_line(self):
        with self.assertRaisesRegex(ValueError, r"a.model:12: expected '<address><TAB><size><TAB><name>'"):
            parse_model_file(sdk_text([(0, 2, "Model Number")]) + "6 1 Firmware Version\n", "a.model")
        with self.assertRaisesRegex(ValueError, "'ID' is listed twice"):
            sdk_file("a.model", [(7, 1, "ID"), (8, 1, "ID")])
        with self.assertRaisesRegex(ValueError, "no \\[control table\\] section"):
            parse_model_file("[type info]\nname\tvalue\n", "a.model")
        with self.assertRaisesRegex(ValueError, "expected the header"):
            parse_model_file("[control table]\n0\t2\tModel Number\n", "a.model")
        with self.assertRaisesRegex(ValueError, "has no rows"):
            parse_model_file("[control table]\nAddress\tSize\tData Name\n", "a.model")


class ModelViewsTest(unittest.TestCase):
    def test_indirect_blocks_number_their_slots_across_blocks(self):
        got = indirect_items([{"address": 168, "data": 224, "count": 2}, {"address": 578, "data": 634, "count": 1}],
                             "t")
        self.assertEqual([(i.name, i.address, i.size) for i in got],
                         [("Indirect Address 1", 168, 2), ("Indirect Data 1", 224, 1),
                          ("Indirect Address 2", 170, 2), ("Indirect Data 2", 225, 1),
                          ("Indirect Address 3", 578, 2), ("Indirect Data 3", 634, 1)])

    def test_a_firmware_variant_replaces_the_indirect_items_and_adds_its_notes(self):
        m = model("xl330-m288", 1200, x330_items(), firmware=53, notes=["a"],
                  variants=[{"firmware_version": 52, "indirect": FW52_INDIRECT, "notes": ["b"]}])
        default, variant = m.views
        self.assertEqual((default.firmware_version, default.variant, variant.firmware_version, variant.variant),
                         (53, False, 52, True))
        self.assertEqual(len(default.items), 3 + 16)
        self.assertEqual([(i.name, i.address) for i in variant.items if i.name.startswith("Indirect Data")],
                         [("Indirect Data 1", 200), ("Indirect Data 2", 201), ("Indirect Data 3", 202),
                          ("Indirect Data 4", 203)])
        self.assertEqual((default.notes, variant.notes), (("a",), ("a", "b")))
        self.assertEqual(variant.label, "xl330-m288 (firmware 52, variant)")

    def test_a_variant_without_indirect_blocks_keeps_the_items(self):
        m = model("x", 1, x330_items(), variants=[{"firmware_version": 40}])
        self.assertEqual(m.views[1].items, m.views[0].items)

    def test_bad_model_files_are_refused_naming_the_place(self):
        with self.assertRaisesRegex(ValueError, "x.json: /items/0: needs key, name, address and size"):
            model("x", 1, [{"name": "ID", "address": 7}])
        with self.assertRaisesRegex(ValueError, "x.json: /firmware_variants/0: needs firmware_version"):
            model("x", 1, BASIC_ITEMS, variants=[{"indirect": []}])
        with self.assertRaisesRegex(ValueError, "needs name, model_number and firmware_version"):
            model_from_json({"name": "x", "items": []}, "x.json")


class NamesTest(unittest.TestCase):
    def view(self, items):
        return model("m", 1, items).default

    def test_names_fold_case_and_punctuation_and_spell_like_keys(self):
        self.assertEqual(folded("BUS Watchdog"), folded("Bus Watchdog"))
        self.assertEqual(spelled("Sencondary(Shadow) ID"), "secondary_id")
        self.assertEqual(spelled("secondary_id"), "secondary_id")
        self.assertEqual(spelled("Baud Rate (Bus)"), "baud_rate")

    def test_each_rule_finds_its_item_and_says_which_rule(self):
        v = self.view([item("Bus Watchdog", 98, 1), item("Sencondary(Shadow) ID", 12, 1, key="sencondary_id"),
                       item("Protocol Version", 13, 1), item("Indirect Address 4", 174, 2),
                       item("Indirect Data 4", 227, 1)])
        cases = [("Bus Watchdog", 98, "name", "Bus Watchdog"), ("BUS Watchdog", 98, "case", "Bus Watchdog"),
                 ("Secondary ID", 12, "spelling", "Sencondary(Shadow) ID"),
                 ("Protocol Type", 13, "alias", "Protocol Version"),
                 ("Indirect Address Read", 174, "indirect alias", "Indirect Address 4"),
                 ("Indirect Data Read", 227, "indirect alias", "Indirect Data 4")]
        for sdk_name, address, rule, name in cases:
            with self.subTest(sdk_name):
                found = find(sdk_name, address, v)
                self.assertEqual((found.rule, found.item.name), (rule, name))

    def test_a_key_is_matched_when_the_name_is_spelled_otherwise(self):
        v = self.view([item("Shadow ID", 12, 1, key="secondary_id")])
        self.assertEqual(find("Secondary ID", 12, v).item.name, "Shadow ID")

    def test_an_indirect_alias_needs_an_item_of_its_kind_at_the_sdk_address(self):
        v = self.view([item("Indirect Address 21", 208, 2)])
        self.assertEqual(find("Indirect Data Write", 208, v).items, ())
        self.assertEqual(find("Indirect Address Write", 208, v).item.name, "Indirect Address 21")
        self.assertEqual(find("Indirect Address Write", 210, v).items, ())

    def test_an_unknown_name_finds_nothing_and_a_name_two_items_match_finds_both(self):
        v = self.view([item("LED", 65, 1), item("Goal PWM", 100, 2), item("Goal-PWM", 102, 2, key="goal_pwm2")])
        self.assertIsNone(find("Present Load", 126, v).rule)
        self.assertEqual(find("Present Load", 126, v).items, ())
        found = find("goal pwm", 100, v)
        self.assertEqual((found.rule, len(found.items), found.item), ("case", 2, None))


class PairingTest(unittest.TestCase):
    def files(self, *names):
        return {n: sdk_file(n, BASIC_ROWS) for n in names}

    def test_a_model_pairs_by_number_and_a_name_alone_does_not_take_a_registered_file(self):
        # rh_p12_rn.model is the RH-P12-RN(A) (35074); the RH-P12-RN (35073) has no SDK file.
        models = [model("rh-p12-rn", 35073, BASIC_ITEMS), model("rh-p12-rna", 35074, BASIC_ITEMS)]
        p = pair({"rh_p12_rn.model": 35074}, self.files("rh_p12_rn.model"), models)
        self.assertEqual(p.pairs, {"rh_p12_rn.model": "rh-p12-rna"})
        self.assertEqual([(c.sdk.file, c.view.name, c.expected_number) for c in p.comparisons],
                         [("rh_p12_rn.model", "rh-p12-rna", 35074)])
        self.assertEqual(p.models_without_sdk,
                         [("rh-p12-rn", 35073, "rh_p12_rn.model is 35074, paired with rh-p12-rna")])

    def test_an_unregistered_file_pairs_by_name_and_a_shared_number_adds_the_registered_file(self):
        # xw430_t200.model is not in dynamixel.model; its page prints 1270, XW430-T333's number.
        models = [model("xw430-t200", 1270, BASIC_ITEMS), model("xw430-t333", 1270, BASIC_ITEMS)]
        p = pair({"xw430_t333.model": 1270}, self.files("xw430_t200.model", "xw430_t333.model"), models)
        self.assertEqual(p.pairs, {"xw430_t200.model": "xw430-t200", "xw430_t333.model": "xw430-t333"})
        self.assertEqual(p.shared, [("xw430_t333.model", "xw430-t200")])
        got = sorted((c.sdk.file, c.view.name, c.expected_number, c.how.split(" ")[0]) for c in p.comparisons)
        self.assertEqual(got, [("xw430_t200.model", "xw430-t200", None, "file"),
                               ("xw430_t333.model", "xw430-t200", 1270, "shares"),
                               ("xw430_t333.model", "xw430-t333", 1270, "model")])

    def test_a_number_two_models_print_goes_to_the_one_named_like_the_file(self):
        # The XC430-T150BB page prints the XC430-W150's number.
        models = [model("xc430-t150bb", 1070, BASIC_ITEMS), model("xc430-w150", 1070, BASIC_ITEMS)]
        p = pair({"xc430_w150.model": 1070}, self.files("xc430_w150.model"), models)
        self.assertEqual(p.pairs, {"xc430_w150.model": "xc430-w150"})
        self.assertEqual(p.shared, [("xc430_w150.model", "xc430-t150bb")])

    def test_a_number_no_model_name_settles_is_an_error(self):
        models = [model("a", 7, BASIC_ITEMS), model("b", 7, BASIC_ITEMS)]
        p = pair({"c.model": 7}, self.files("c.model"), models)
        self.assertEqual(p.errors, ["c.model: models a, b all have 7 and none has the file's name"])

    def test_a_registered_file_found_by_name_checks_the_number(self):
        models = [model("xd430-t350", 1002, BASIC_ITEMS)]
        p = pair({"xd430_t350.model": 1001}, self.files("xd430_t350.model"), models)
        self.assertEqual([(c.view.name, c.expected_number) for c in p.comparisons], [("xd430-t350", 1001)])
        diffs = compare(p.comparisons[0])[1]
        self.assertEqual([(d.item, d.text) for d in diffs],
                         [("Model Number", "the model reports 1002, dynamixel.model registers xd430_t350.model "
                                           "as 1001")])

    def test_files_without_a_model_and_models_without_a_file_are_listed(self):
        p = pair({"xd430_t350.model": 1001}, self.files("xd430_t350.model", "xw430_t200.model"),
                 [model("ax-12a", 12, BASIC_ITEMS)])
        self.assertEqual(p.sdk_without_model, [("xd430_t350.model", 1001), ("xw430_t200.model", None)])
        self.assertEqual(p.models_without_sdk, [("ax-12a", 12, "DynamixelSDK ships no table for it")])
        self.assertEqual(p.comparisons, [])

    def test_each_firmware_is_compared_with_the_table_it_selects(self):
        files = {"xl330_m288.model": sdk_file("xl330_m288.model", X330_ROWS),
                 "xl330_m288_fw52.model": sdk_file("xl330_m288_fw52.model", FW52_ROWS)}
        m = model("xl330-m288", 1200, x330_items(), firmware=53,
                  variants=[{"firmware_version": 52, "indirect": FW52_INDIRECT}])
        p = pair({"xl330_m288.model": 1200}, files, [m])
        self.assertEqual([(c.sdk.file, c.view.firmware_version) for c in p.comparisons],
                         [("xl330_m288.model", 53), ("xl330_m288_fw52.model", 52)])
        self.assertEqual(p.not_compared, [])
        result = check(p.comparisons, None)
        self.assertEqual((result.compared_items, result.differences), (2 * len(X330_ROWS), []))
        self.assertEqual(select_file(m.views[1], list(files.values())).file, "xl330_m288_fw52.model")

    def test_a_fw52_table_without_a_variant_is_not_compared(self):
        files = {"xl330_m288.model": sdk_file("xl330_m288.model", X330_ROWS),
                 "xl330_m288_fw52.model": sdk_file("xl330_m288_fw52.model", FW52_ROWS)}
        p = pair({"xl330_m288.model": 1200}, files, [model("xl330-m288", 1200, x330_items(), firmware=53)])
        self.assertEqual([c.sdk.file for c in p.comparisons], ["xl330_m288.model"])
        self.assertEqual(p.not_compared,
                         [("xl330_m288_fw52.model", "no variant (xl330-m288 has no firmware variant 52 or older)")])
        self.assertEqual(p.firmware_info, [])

    def test_a_default_firmware_that_selects_the_older_table_is_told_then_fails_with_variants(self):
        # Firmware 46 with the V53 layout: a client picking its table by Firmware Version (ROS 2)
        # loads the fw52 table. Without variants the model claims no layout per firmware.
        files = {"xl330_m288.model": sdk_file("xl330_m288.model", X330_ROWS),
                 "xl330_m288_fw52.model": sdk_file("xl330_m288_fw52.model", FW52_ROWS)}
        p = pair({"xl330_m288.model": 1200}, files, [model("xl330-m288", 1200, x330_items(), firmware=46)])
        self.assertEqual([c.sdk.file for c in p.comparisons], ["xl330_m288.model"])
        self.assertEqual(p.firmware_info, ["xl330-m288 (firmware 46, default) is compared with xl330_m288.model, "
                                           "but a client that picks its table by Firmware Version loads "
                                           "xl330_m288_fw52.model for firmware 46"])
        self.assertEqual(check(p.comparisons, None).differences, [])
        with_variant = model("xl330-m288", 1200, x330_items(), firmware=46,
                             variants=[{"firmware_version": 52, "indirect": FW52_INDIRECT}])
        p = pair({"xl330_m288.model": 1200}, files, [with_variant])
        self.assertEqual([(c.sdk.file, c.view.firmware_version) for c in p.comparisons],
                         [("xl330_m288.model", 46), ("xl330_m288_fw52.model", 52)])
        diffs = check(p.comparisons, None).differences
        self.assertEqual([(d.sdk_file, d.item) for d in diffs], [("xl330_m288.model", "Firmware Version")])
        self.assertIn("firmware 46 selects xl330_m288_fw52.model", diffs[0].text)

    def test_a_fw_table_without_its_model_table_is_an_error(self):
        p = pair({}, {"a_fw52.model": sdk_file("a_fw52.model", BASIC_ROWS)}, [])
        self.assertEqual(p.errors, ["a_fw52.model: no a.model beside it"])


def comparison(rows, items, expected_number=1, file="m.model", **kw):
    return Comparison(sdk_file(file, rows), model("m", 1, items, **kw).default, "test", expected_number)


class CompareTest(unittest.TestCase):
    def test_address_size_and_missing_items_differ_and_matching_ones_do_not(self):
        count, diffs = compare(comparison(
            [(0, 2, "Model Number"), (7, 1, "ID"), (8, 2, "Baud Rate"), (9, 1, "Protocol Type"),
             (60, 1, "Backup Ready")],
            [item("Model Number", 0, 2), item("ID", 8, 1), item("Baud Rate", 8, 1), item("Protocol Version", 10, 1)]))
        self.assertEqual(count, 5)
        self.assertEqual([d.line() for d in diffs], [
            "m.model vs m (firmware 45, default): ID: SDK address 7, model 8",
            "m.model vs m (firmware 45, default): Baud Rate: SDK size 2, model 1",
            "m.model vs m (firmware 45, default): Protocol Type: SDK address 9, model 10 (the model's "
            "'Protocol Version')",
            "m.model vs m (firmware 45, default): Backup Ready: SDK 60, size 1: no item of the model is this "
            "name or an alias of it (at 60 the model has nothing)"])

    def test_an_ambiguous_name_is_a_difference_no_note_can_explain(self):
        c = comparison([(100, 2, "GOAL PWM")], [item("Goal PWM", 100, 2), item("goal-pwm", 102, 2, key="x")],
                       notes=["sdk-control-tables: m.model GOAL PWM: see control-tables/m.md"])
        result = check([c], None)
        self.assertEqual(len(result.unexplained), 1)
        self.assertFalse(result.unexplained[0].explainable)
        self.assertIn("the test's name mapping is wrong", result.unexplained[0].text)

    def test_indirect_aliases_must_name_one_slot_for_address_and_data(self):
        rows = [(168, 2, "Indirect Address Write"), (224, 1, "Indirect Data Write"),
                (174, 2, "Indirect Address Read"), (228, 1, "Indirect Data Read")]
        _, diffs = compare(comparison(rows, x330_items()))
        self.assertEqual([(d.item, d.text) for d in diffs], [
            ("Indirect Data Read", "Indirect Address Read (174) is the model's Indirect Address 4, but Indirect "
                                   "Data Read (228) is its Indirect Data 5: the SDK reads one slot's data through "
                                   "another's address")])


class NotesTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.pages = Path(self.dir.name)
        (self.pages / "ph42-020-s300-r.md").write_text("# page\n", encoding="utf-8")

    def tearDown(self):
        self.dir.cleanup()

    def test_a_note_names_the_file_the_item_and_the_page(self):
        e = parse_note("sdk-control-tables: ph42_020_s300.model Backup Ready: the page has no row "
                       "(control-tables/ph42-020-s300-r.md, 'no Backup Ready(878) rows')", self.pages)
        self.assertEqual((e.file, e.item, e.pages), ("ph42_020_s300.model", "Backup Ready", ("ph42-020-s300-r.md",)))
        e = parse_note("sdk-control-tables: mx_64.model Secondary(Shadow) ID: x control-tables/ph42-020-s300-r.md",
                       None)
        self.assertEqual(e.item, "Secondary(Shadow) ID")

    def test_malformed_notes_and_missing_pages_are_refused(self):
        with self.assertRaisesRegex(ValueError, "not 'sdk-control-tables: <file>.model <item>: <why>'"):
            parse_note("sdk-control-tables: Backup Ready differs", self.pages)
        with self.assertRaisesRegex(ValueError, "cites no e-Manual page"):
            parse_note("sdk-control-tables: a.model Backup Ready: the SDK is wrong", self.pages)
        with self.assertRaisesRegex(ValueError, "cites control-tables/nope.md, which the reference does not have"):
            parse_note("sdk-control-tables: a.model ID: see control-tables/nope.md", self.pages)

    def test_a_note_explains_its_difference_and_a_stale_or_broken_note_fails(self):
        good = "sdk-control-tables: m.model Backup Ready: not on control-tables/ph42-020-s300-r.md"
        stale = "sdk-control-tables: m.model ID: was once at 8, control-tables/ph42-020-s300-r.md"
        broken = "sdk-control-tables: m.model"
        c = comparison([(7, 1, "ID"), (878, 1, "Backup Ready")], [item("ID", 7, 1)],
                       notes=[good, stale, broken, "range: unrelated"])
        result = check([c], self.pages)
        self.assertEqual(result.compared_items, 2)
        self.assertEqual([(d.item, d.explained_by.note) for d in result.explained], [("Backup Ready", good)])
        self.assertEqual(result.unexplained, [])
        self.assertEqual(len(result.note_errors), 2)
        self.assertIn("not 'sdk-control-tables: <file>.model", result.note_errors[0])
        self.assertIn("explains no difference", result.note_errors[1])
        self.assertIn("'ID'", result.note_errors[1])

    def test_a_note_for_another_sdk_file_explains_nothing_here(self):
        note = "sdk-control-tables: other.model ID: control-tables/ph42-020-s300-r.md"
        result = check([comparison([(7, 1, "ID")], [item("ID", 8, 1)], notes=[note])], self.pages)
        self.assertEqual(len(result.unexplained), 1)
        self.assertEqual(len(result.note_errors), 1)


    def test_a_note_of_a_model_no_sdk_file_reaches_explains_nothing(self):
        note = "sdk-control-tables: rh_p12_rn.model Model Number: 35073 (control-tables/ph42-020-s300-r.md)"
        unpaired = model("rh-p12-rn", 35073, BASIC_ITEMS, notes=[note])
        result = check([], self.pages, [unpaired])
        self.assertEqual(len(result.note_errors), 1)
        self.assertIn("rh-p12-rn: explains no difference", result.note_errors[0])


class RunTest(unittest.TestCase):
    """The whole run on a reference and a models/ directory written here."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        root = Path(self.dir.name)
        self.reference, self.models = root / "reference", root / "models"
        sdk = self.reference / "sdk-control-tables"
        sdk.mkdir(parents=True)
        (self.reference / "control-tables").mkdir()
        (self.reference / "control-tables" / "a-1.md").write_text("# A-1\n", encoding="utf-8")
        (sdk / "dynamixel.model").write_text("Number\tName\n1\ta_1.model\n2\tb_2.model\n", encoding="utf-8")
        (sdk / "a_1.model").write_text(sdk_text(BASIC_ROWS), encoding="utf-8")
        (sdk / "b_2.model").write_text(sdk_text(BASIC_ROWS), encoding="utf-8")
        self.models.mkdir()

    def tearDown(self):
        self.dir.cleanup()

    def write_models(self, *docs):
        for d in docs:
            (self.models / f"{d['name']}.json").write_text(json.dumps(d), encoding="utf-8")
        catalog = {"models": [{"name": d["name"], "model_number": d["model_number"], "file": f"{d['name']}.json"}
                              for d in docs]}
        (self.models / "catalog.json").write_text(json.dumps(catalog), encoding="utf-8")

    def run_check(self):
        out = io.StringIO()
        return runner.run(self.reference, self.models, out), out.getvalue()

    def test_agreeing_models_pass_with_a_summary(self):
        self.write_models(model_doc("a-1", 1, BASIC_ITEMS), model_doc("c-3", 3, BASIC_ITEMS))
        code, text = self.run_check()
        self.assertEqual(code, 0, text)
        self.assertIn("Summary: 1 models both sources know (2 SDK models, 2 model files; 0 more by a shared "
                      "model number), 3 items compared in 1 comparisons, 0 explained differences, 0 unexplained",
                      text)
        self.assertIn("SDK models with no model file yet (informational) (1):\n  b_2.model (2)", text)
        self.assertIn("Models with no SDK file (informational) (1):\n  c-3 (3)", text)
        self.assertTrue(text.endswith("OK\n"))

    def test_a_difference_fails_until_a_note_explains_it(self):
        moved = [item("Model Number", 0, 2), item("Firmware Version", 6, 1), item("ID", 8, 1)]
        self.write_models(model_doc("a-1", 1, moved))
        code, text = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("UNEXPLAINED DIFFERENCES (1):\n  a_1.model vs a-1 (firmware 45, default): ID: SDK address 7, "
                      "model 8", text)
        self.write_models(model_doc("a-1", 1, moved, notes=[
            "sdk-control-tables: a_1.model ID: the page prints 8 (control-tables/a-1.md)"]))
        code, text = self.run_check()
        self.assertEqual(code, 0, text)
        self.assertIn("1 explained differences, 0 unexplained", text)

    def test_a_firmware_table_fails_until_the_model_has_its_variant(self):
        sdk = self.reference / "sdk-control-tables"
        (sdk / "a_1.model").write_text(sdk_text(X330_ROWS), encoding="utf-8")
        (sdk / "a_1_fw52.model").write_text(sdk_text(FW52_ROWS), encoding="utf-8")
        self.write_models(model_doc("a-1", 1, x330_items(), firmware=53))
        code, text = self.run_check()
        self.assertEqual(code, 1, text)
        self.assertIn("Pairing errors (1):\n  a_1_fw52.model: no variant (a-1 has no firmware variant 52 or older)",
                      text)
        self.write_models(model_doc("a-1", 1, x330_items(), firmware=53,
                                    variants=[{"firmware_version": 52, "indirect": FW52_INDIRECT,
                                               "notes": ["older"]}]))
        code, text = self.run_check()
        self.assertEqual(code, 0, text)
        self.assertIn("2 comparisons", text)

    def test_a_missing_reference_fails_saying_so(self):
        self.write_models(model_doc("a-1", 1, BASIC_ITEMS))
        out = io.StringIO()
        code = runner.run(self.reference / "nowhere", self.models, out)
        self.assertEqual(code, 1)
        self.assertIn("FAIL: no ", out.getvalue())
        self.assertIn("sdk-control-tables/ in the reference", out.getvalue())

    def test_a_registered_file_that_is_absent_fails(self):
        (self.reference / "sdk-control-tables" / "b_2.model").unlink()
        self.write_models(model_doc("a-1", 1, BASIC_ITEMS))
        code, text = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("dynamixel.model lists b_2.model, which", text)

    def test_a_catalog_that_disagrees_with_its_file_fails(self):
        self.write_models(model_doc("a-1", 1, BASIC_ITEMS))
        (self.models / "catalog.json").write_text(json.dumps({"models": [
            {"name": "a-1", "model_number": 5, "file": "a-1.json"}]}), encoding="utf-8")
        code, text = self.run_check()
        self.assertEqual(code, 1)
        self.assertIn("catalog.json says a-1 5, a-1.json says a-1 1", text)


if __name__ == "__main__":
    unittest.main()
