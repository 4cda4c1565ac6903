"""The items of one page: keys, access, ranges (item_ranges.py), signedness, the accepted values
of Operating Mode, Protocol Type and Baud Rate, and the power-on values the pages print as '-'.

build_items runs the passes in their order; each pass reads what the earlier ones decided.
"""

from __future__ import annotations

import re

from . import item_ranges
from .decisions.catalogue import P2_FAMILIES, classify
from .decisions.item_rules import (ANGLE_LIMIT_FAMILIES, BAUD_RATE_VALUES, BORROWED_ROW_NOTE, BUS_WATCHDOG_FAMILIES,
                                   INITIAL_OVERRIDES, INITIAL_RULES, KEY_ALIASES, MID_POSITION, OPMODE_BLOCKS,
                                   OPMODE_VALUES,
                                   PROTOCOL_TYPE_BLOCKS, SIGNED_MODEL_NOTES, SIGNED_READBACK,
                                   SIGNED_READBACK_FAMILIES, TWIN_PAGES, ZERO_REASONS, InitialRule)
from .items import Draft, Item
from .markdown import clean_cell, clean_unit, parse_int, snake_key, tables_in, unit_number
from .page import Row, read_page


def build_items(d: Draft, fw: int) -> None:
    """All passes over the items of `d`; `fw` is the model's firmware_version."""
    make_items(d)
    item_ranges.printed_ranges(d)
    item_ranges.fill_unprinted_ranges(d)
    operating_modes(d)
    signedness(d)
    protocol_type_values(d)
    baud_rate_values(d)
    item_ranges.resolve_limits(d)
    initial_values(d, fw)
    item_ranges.widen_to_factory(d)
    angle_limit_note(d)
    item_ranges.limit_max_overrides(d)
    item_ranges.check_description_agreement(d)


def make_items(d: Draft):
    """One item per row: key (snake_case of the name; with the address where two rows share it),
    unit, and the note on 'R/RW' access."""
    keys_seen: dict[str, Row] = {}
    for row in d.page.rows:
        key = snake_key(row.name)
        item = Item(row, key)
        if key in KEY_ALIASES:
            key, note = KEY_ALIASES[key]
            item.key = key
            item.notes.append(note)
        if key in keys_seen:
            item.key = f"{key}_{row.address}"
            item.notes.append(f"key: '{key}' is also the key of {keys_seen[key].name}({keys_seen[key].address}); "
                              f"disambiguated with the address")
        keys_seen[key] = row
        if row.borrowed:
            item.notes.append(BORROWED_ROW_NOTE.format(donor=row.borrowed))
        if row.by_protocol:
            mark = ", with footnote mark 1)" if row.by_protocol.endswith("1)") else ""
            item.notes.append(f"initial: the page prints '{row.by_protocol}', one value per protocol (DYNAMIXEL "
                              f"Protocol 2.0, then Modbus{mark}); the Protocol 2.0 value is used: this model "
                              f"does not speak Modbus RTU in dxlemu (see the protocols note)")
        if row.access == "R/RW":
            item.notes.append("access: the page prints 'R/RW' (read-only or writable depending on "
                              "External Port Mode); RW is used and the mode check is left to the emulator")
        unit = clean_unit(row.unit)
        item.unit = unit
        d.add(item)


def page_has_extended_mode(d: Draft) -> bool:
    """True when the model's Operating Mode accepts 4 (Extended Position Control Mode)."""
    mode = next((i for i in d.items if i.key == "operating_mode"), None)
    return mode is not None and (4 in (mode.values or []) or
                                 (mode.max is not None and mode.max >= 4))


def signedness(d: Draft):
    """Signed items: negative ranges or bounds, the read-backs of SIGNED_READBACK, a Goal Position
    that Extended Position Control Mode drives below zero, and Bus Watchdog."""
    for item in d.items:
        if (item.min is not None and item.min < 0) or (item.values and min(item.values) < 0):
            item.signed = True
        if item.limit_min and item.limit_min.startswith("-"):
            item.signed = True
        if d.is_in(SIGNED_READBACK_FAMILIES) and item.key in SIGNED_READBACK and not item.signed:
            item.signed = True
            item.notes.append("signed: the page prints no range, but the device reports this value in "
                              "two's complement (negative for reverse direction / below zero)")
        if (item.key == "goal_position" and d.is_in(P2_FAMILIES) and not item.signed
                and page_has_extended_mode(d)):
            item.signed = True
            item.notes.append("signed: Extended Position Control Mode (Operating Mode 4) takes goals of "
                              "-256 ~ 256 rev in two's complement (opmode include); the range rule of the "
                              "motion model widens the static range in that mode")
        if item.key == "bus_watchdog" and d.is_in(BUS_WATCHDOG_FAMILIES):
            item.signed = True
            printed = f"{item.min} ~ {item.max}"
            why = ""
            if item.min and item.min > 0:
                item.min = 0
                why = (f"range: {printed} is printed for the active values; 0 (deactivate, clear the "
                       f"watchdog error) is accepted too, per the Bus Watchdog include's Values table; ")
            item.notes.append(f"{why}signed: the device itself sets -1 (0x{'FF' * item.row.size}) on a watchdog timeout (Bus "
                              f"Watchdog include), so the item is signed; writes accept {item.min} ~ {item.max}")
    d.notes += [note for families, note in SIGNED_MODEL_NOTES if d.is_in(families)]


def operating_modes(d: Draft):
    """Operating Mode values from the first OPMODE_BLOCKS block the page shows."""
    item = d.by_key.get("operating_mode")
    if item is None:
        return
    if item.values is not None and item.range_from != "donor":   # P / PRO print the list
        return
    if d.is_in(OPMODE_VALUES):
        item.values, note = d.lookup(OPMODE_VALUES)
        item.min = item.max = None
        item.notes.append(note)
        return
    text = d.page.text
    for block in OPMODE_BLOCKS:
        if any(marker in text for marker in block.markers):
            assert not block.without_item or block.without_item not in d.by_key
            item.values = mode_values(d, block.include)
            item.notes.append(block.note or f"values: the modes listed in {block.include}.md (the page's "
                                            f"Operating Mode block)")
            return
    for sec in d.page.section_for(item.row.address):
        values = mode_table_values(d.page.section_text(sec, d.ref))
        if values:
            item.values = values
            item.notes.append("values: the modes of the Value table in the page's Operating Mode section, "
                              "without the rows it marks Reserved (they replace any donor page's list)")
            return
    raise ValueError(f"{d.name}: no Operating Mode block recognised")


def mode_table_values(text: str) -> list[int]:
    """The mode numbers of the first Value table in `text`, skipping 'Reserved' rows ('1 ~ 4')."""
    for tab in tables_in(text.splitlines()):
        if tab.header and tab.header[0].lower() == "value":
            return [int(m.group(1)) for cells in tab.rows
                    if "reserved" not in " ".join(cells).lower()
                    for m in [re.match(r"\s*(\d+)", clean_cell(cells[0]))] if m]
    return []


def mode_values(d: Draft, include: str) -> list[int]:
    """The numbers of the first Value table of an include (the modes an Operating Mode block lists)."""
    text = d.ref.include(include, d.page.group)
    values = []
    for tab in tables_in(text.splitlines()):
        if tab.header and tab.header[0].lower() == "value":
            for cells in tab.rows:
                n = re.match(r"\s*(\d+)", clean_cell(cells[0]))
                if n:
                    values.append(int(n.group(1)))
            break
    if not values:
        raise ValueError(f"no mode table in {include}")
    return values


def protocol_type_values(d: Draft):
    """Protocol Type values from the variant's include (PROTOCOL_TYPE_BLOCKS)."""
    item = d.by_key.get("protocol_type")
    block = d.lookup(PROTOCOL_TYPE_BLOCKS, None)
    if item is None or block is None:
        return
    include, note, group = block
    text = d.ref.include(include, group or d.page.group)
    tab = next(t for t in tables_in(text.splitlines()) if t.header[0].lower() == "value")
    item.values = [int(re.match(r"\s*(\d+)", clean_cell(c[0])).group(1)) for c in tab.rows]
    item.notes.append(note.format(values=", ".join(map(str, item.values))))


def baud_rate_values(d: Draft):
    """Baud Rate values where the table's range names indices without a rate (BAUD_RATE_VALUES)."""
    if d.is_in(BAUD_RATE_VALUES):
        values, note = d.lookup(BAUD_RATE_VALUES)
        item = d.by_key["baud_rate"]
        item.values = list(values)
        item.notes.append(note)


def initial_values(d: Draft, fw: int):
    """Power-on values: the printed number, else INITIAL_RULES, else 0 for a ZERO_REASONS reason."""
    for item in d.items:
        text = item.row.initial
        n = parse_int(text)
        override = INITIAL_OVERRIDES.get((d.name, item.key))
        if override is not None:
            item.initial = override[0]
            item.notes.append(override[1])
            continue
        if n is not None:
            item.initial = n
            continue
        what = "'-'" if text in ("-", "") else f"'{text}'"
        rule = INITIAL_RULES.get(item.key)
        if rule is not None and (not rule.printed or re.fullmatch(rule.printed, text, re.I)):
            if apply_initial_rule(d, item, rule, what, fw):
                continue
        item.initial = 0
        reason = next((r for pat, r in ZERO_REASONS if re.fullmatch(pat, item.key)), None)
        if reason is None:
            raise ValueError(f"{d.name}.{item.key}: initial {what} and no rule for it")
        item.notes.append(f"initial: the page shows {what}; 0 chosen ({reason})")


def supply_voltage(d: Draft, item: Item, fw: int) -> tuple[int, dict] | None:
    """The midpoint of the factory voltage limits, where the model has both."""
    low, high = d.by_key.get("min_voltage_limit"), d.by_key.get("max_voltage_limit")
    if not (low and high):
        return None
    midpoint = (low.initial + high.initial) // 2
    # The reading may count finer than the limits (DYNAMIXEL-Y: limits in 0.1 V, Present Input
    # Voltage in 0.01 V): the midpoint is given in the reading's unit.
    limit_unit, reading_unit = unit_number(low.unit), unit_number(item.unit)
    if limit_unit and reading_unit and limit_unit != reading_unit:
        midpoint = round(midpoint * limit_unit / reading_unit)
        item.notes.append(f"unit: the Voltage Limits count {low.unit}, this reading {item.unit}; the "
                          f"midpoint is written in the reading's unit")
    return midpoint, {"low": low.initial, "high": high.initial}


def twin_page(d: Draft, item: Item, fw: int) -> tuple[int, dict] | None:
    """The printed factory value of the same item on the page TWIN_PAGES pairs with this one."""
    twin = TWIN_PAGES.get(d.name)
    if twin is None:
        return None
    rows = [r for r in read_page(d.ref, twin, *classify(twin)).rows if r.address == item.row.address]
    if len(rows) != 1 or snake_key(rows[0].name) != snake_key(item.row.name) or parse_int(rows[0].initial) is None:
        raise ValueError(f"{d.name}.{item.key}: {twin} prints no factory value at {item.row.address}")
    return parse_int(rows[0].initial), {"twin": twin}


# Families whose Moving Status has a Position In Range bit (DYNAMIXEL-Y: bit 6), set at rest.
POSITION_IN_RANGE_BIT = {"y": 0x40}


def moving_status_at_rest(d: Draft, item: Item, fw: int) -> tuple[int, dict] | None:
    """Moving Status at power-on where it reports Position In Range; None (0, not moving) elsewhere."""
    bit = d.lookup(POSITION_IN_RANGE_BIT, None)
    low, high = d.by_key.get("min_position_limit"), d.by_key.get("max_position_limit")
    if bit is None or not (low and high) or not low.initial <= d.lookup(MID_POSITION) <= high.initial:
        return None
    return bit, {}


# The values InitialRule.computed names: (draft, item, firmware version) -> (value, further note
# fields) or None when the model lacks what the value is computed from.
INITIAL_COMPUTATIONS = {
    "firmware_version": lambda d, item, fw: (fw, {}),
    "mid_position": lambda d, item, fw: (d.lookup(MID_POSITION), {}),
    "supply_voltage": supply_voltage,
    "range_top": lambda d, item, fw: (item.static_range()[1], {}),
    "twin_page": twin_page,
    "moving_status_at_rest": moving_status_at_rest,
}


def apply_initial_rule(d: Draft, item: Item, rule: InitialRule, what: str, fw: int) -> bool:
    """Sets the item's power-on value by `rule`; False when the rule has nothing to compute from."""
    fields = {}
    if rule.copy_from:
        item.initial_from = rule.copy_from
    elif rule.computed:
        got = INITIAL_COMPUTATIONS[rule.computed](d, item, fw)
        if got is None:
            return False
        item.initial, fields = got
    else:
        item.initial = rule.value
    item.notes.append(rule.note.format(what=what, value=item.initial, **fields))
    return True


def angle_limit_note(d: Draft):
    """AX/RX/EX/MX 1.0 and XL-320: CW/CCW Angle Limit bound Goal Position only in joint mode."""
    if not d.is_in(ANGLE_LIMIT_FAMILIES):
        return
    item = d.by_key["goal_position"]
    multi = d.lookup(ANGLE_LIMIT_FAMILIES)
    item.notes.append("limits: CW/CCW Angle Limit(6, 8) bound Goal Position in joint mode only, and a goal "
                      "outside them raises the Angle Limit Error bit rather than a range error; they do not "
                      f"apply in wheel mode (both 0){multi}. limit_min/limit_max cannot express a "
                      "mode-dependent bound, so none is set and the family code applies the rule (README 32)")
