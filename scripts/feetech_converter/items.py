"""The items of one FEETECH model: FEETECH's wiki table row by row, read as printed, with the
decisions (decisions.py) where a cell says '–' or a sentence, and the ST3215 spreadsheet's values
where the model has one and the wiki prints none."""

from __future__ import annotations

import re

from model_converter.markdown import parse_int, snake_key

from .decisions import MODEL_NUMBER_NOTE, Family, Model
from .reference import SECTION_AREAS, FeetechReference, SheetRow, WikiRow

UNDEFINED = {"undefined", "reserved"}
DASHES = {"", "–", "-"}
DIRECTION = re.compile(r"BIT(\d+) is the (?:\w+ )?direction bit")


def parse_range(text: str) -> tuple[int, int] | None:
    """'0~4094', '-32767~32767', '40 ~ 59' -> (lo, hi); '–' or empty -> None."""
    if text in DASHES:
        return None
    found = re.fullmatch(r"(-?\d+)\s*~\s*(-?\d+)", text)
    if not found:
        raise ValueError(f"range {text!r} not understood")
    return int(found.group(1)), int(found.group(2))


def full_range(size: int, sign_bit: int | None) -> tuple[int, int]:
    """Every value an item can hold (the loader's default range)."""
    if sign_bit is not None:
        top = (1 << sign_bit) - 1
        return -top, top
    return 0, (1 << (8 * size)) - 1


def sign_bit_of(row: WikiRow, address: int, family: Family, notes: list[str]) -> int | None:
    """The sign bit: the family's decision, else the description's 'BITn is the direction bit'."""
    if address in family.sign_bits:
        bit, note = family.sign_bits[address]
        notes.append(note)
        return bit
    bits = {int(b) for b in DIRECTION.findall(row.description)}
    if len(bits) > 1:
        raise ValueError(f"address {address}: the description names direction bits {sorted(bits)}; "
                         "decide one in decisions.py")
    if bits:
        bit = bits.pop()
        notes.append(f"sign_bit: {bit}, the wiki's 'BIT{bit} is the direction bit' (sign-magnitude)")
        return bit
    return None


def item_range(row: WikiRow, address: int, size: int, bit: int | None, family: Family,
               notes: list[str]) -> tuple[int, int]:
    """The range: the family's decision, else the Range cell, widened to its negative when a
    direction bit makes a printed 0~N signed; the full width where the cell prints none."""
    if address in family.ranges:
        bounds, note = family.ranges[address]
        notes.append(note)
        return bounds
    printed = parse_range(row.range)
    if printed is None:
        return full_range(size, bit)
    lo, hi = printed
    if bit is not None and lo == 0:
        notes.append(f"range: the wiki prints {row.range} with a direction bit: -{hi}~{hi}")
        return -hi, hi
    return lo, hi


def initial_of(row: WikiRow, address: int, model: Model, family: Family, sheet: dict[int, SheetRow],
               notes: list[str]) -> int | str:
    """The power-on value: the printed number; where it prints '–' or a sentence, the model's or
    the family's decision, else the ST3215 spreadsheet's value."""
    printed = parse_int(row.initial)
    row_sheet = sheet.get(address)
    if printed is not None:
        if row_sheet and row_sheet.initial is not None and row_sheet.initial != printed:
            notes.append(f"initial: {printed} as the wiki prints it; the ST3215 spreadsheet says {row_sheet.initial}")
        return printed
    if address in model.initials:
        value, note = model.initials[address]
    elif address in family.initials:
        value, note = family.initials[address]
    elif row_sheet and row_sheet.initial is not None and row_sheet.size == int(row.size):
        value, note = row_sheet.initial, (f"initial: the wiki prints '{row.initial}'; {row_sheet.initial}, the "
                                          "ST3215 spreadsheet's value")
    else:
        raise ValueError(f"address {address} ({row.function}): the wiki prints initial {row.initial!r} and no "
                         "decision gives one")
    notes.append(note)
    return value


def sheet_differences(row: SheetRow, size: int, lo: int, hi: int) -> list[str]:
    """Where the ST3215 spreadsheet gives another size or range than the model (its initial
    values are compared in initial_of())."""
    notes = []
    if row.size != size:
        notes.append(f"size: {size} as the wiki prints it; the ST3215 spreadsheet says {row.size}")
    if row.minimum is not None and row.maximum is not None and (row.minimum, row.maximum) != (lo, hi):
        notes.append(f"range: {lo}~{hi}; the ST3215 spreadsheet says {row.minimum}~{row.maximum}")
    return notes


def build_items(ref: FeetechReference, model: Model, family: Family) -> list[dict]:
    """The model's items in address order."""
    sheet = {r.address: r for r in ref.sheet}
    items: dict[int, dict] = {}
    for row in ref.wiki:
        address = parse_int(row.address)
        if address is None or row.function.lower() in UNDEFINED:
            continue  # a span such as '50~54' or an Undefined/Reserved row: a gap, not an item
        if address == 4:
            continue  # the model number's high (STS/SMS/HLS) or low (SCS) byte, see address 3
        items[address] = make_item(row, address, model, family, sheet)
    for address, fields in family.added.items():
        if address in items:
            raise ValueError(f"address {address} is added by decisions.py but the wiki defines it")
        items[address] = {"key": fields["key"], "name": fields["name"], "address": address,
                          **{k: v for k, v in fields.items() if k not in ("key", "name")}}
    return [items[a] for a in sorted(items)]


def make_item(row: WikiRow, address: int, model: Model, family: Family, sheet: dict[int, SheetRow]) -> dict:
    """One item from its wiki row."""
    notes: list[str] = []
    size = int(row.size)
    key = family.keys.get(address, snake_key(row.function))
    name = row.function
    if row.access not in ("R", "R/W"):
        raise ValueError(f"address {address}: access {row.access!r} not understood")
    access = "R" if row.access == "R" else "RW"
    if address == 3:
        key, name, size = "model_number", "Model number", 2
        notes.append(MODEL_NUMBER_NOTE)
        initial: int | str = model.model_number
        bit, (lo, hi) = None, full_range(2, None)
    else:
        bit = sign_bit_of(row, address, family, notes)
        lo, hi = item_range(row, address, size, bit, family, notes)
        if address in (0, 1):
            initial = model.firmware[address]
            notes.append(f"initial: the wiki prints '{row.initial}'; see firmware_version")
            if parse_int(row.initial) is not None and parse_int(row.initial) != initial:
                raise ValueError(f"address {address}: firmware {initial} differs from the wiki's {row.initial}")
        else:
            initial = initial_of(row, address, model, family, sheet, notes)
    if address in sheet:
        notes.extend(sheet_differences(sheet[address], size, lo, hi))
    item: dict = {"key": key, "name": name, "address": address, "size": size, "access": access,
                  "area": SECTION_AREAS[row.section]}
    if isinstance(initial, str):
        item["initial_from"] = initial
    else:
        item["initial"] = initial
    if bit is not None:
        item["sign_bit"] = bit
    if (lo, hi) != full_range(size, bit):
        item["min"], item["max"] = lo, hi
    if address in family.values:
        values, note = family.values[address]
        item["values"] = values
        item.pop("min", None)
        item.pop("max", None)
        notes.append(note)
    if row.unit not in DASHES and row.unit != "None":
        item["unit"] = row.unit
    if notes:
        item["note"] = "; ".join(notes)
    return item
