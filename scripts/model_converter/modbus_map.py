"""The Modbus RTU register map of a model that lists "modbus": the page's Modbus Address column,
checked row by row against the rule every DYNAMIXEL-P page follows, and the items it prints 'N/A'
marked `absent_in` Modbus.

The rule (modbus/modbus-rtu.md "Register map"): holding register 40001 + floor(address / 2) holds
the control-table bytes 2R and 2R + 1, the even address its low byte; a 1-byte item is printed
'4xxxx (Lo Byte)' or '4xxxx (Hi Byte)', a 2- or 4-byte item (at an even address) by its first
register. The emulator applies the rule (docs/modbus.md); nothing else of the column goes into
the model, so a printed address that breaks it refuses the page unless decisions/modbus.py
names the row, with its evidence.
"""

from __future__ import annotations

import re

from .decisions.modbus import MODBUS_ERRATA, MODBUS_FIRMWARE
from .items import Draft, Item
from .page import numbered

MODBUS = "modbus"
REGISTER_BASE = 40001        # the "4xxxx" notation's first holding register (PDU address 0)
NOT_MAPPED = "N/A"


def expected_cell(address: int, size: int) -> str:
    """The Modbus Address cell the rule gives an item: '40004 (Hi Byte)' for a 1-byte item at 7."""
    register = REGISTER_BASE + address // 2
    if size == 1:
        return f"{register} ({'Lo' if address % 2 == 0 else 'Hi'} Byte)"
    if address % 2:
        raise ValueError(f"a {size}-byte item at the odd address {address} straddles two registers")
    return str(register)


def same_cell(printed: str, expected: str) -> bool:
    """True when a printed cell says what the rule gives (spacing and letter case aside)."""
    def norm(text: str) -> str:
        return re.sub(r"\s+", " ", text).strip().lower()
    return norm(printed) == norm(expected)


def read_modbus_map(d: Draft, fw: int, variant_firmware: list[int]) -> None:
    """Marks the items the page prints 'N/A' absent in Modbus and checks every other row's cell;
    refuses (ValueError, naming the row) a cell that breaks the rule and is no erratum, a row
    without a cell, and a firmware below the one Modbus needs. Adds the model's modbus notes."""
    if "modbus" not in d.page.columns:
        raise ValueError(f"{d.name}: lists Modbus RTU, but the page has no Modbus Address column")
    lowest, evidence = d.lookup(MODBUS_FIRMWARE)
    for version in (fw, *variant_firmware):
        if version < lowest:
            raise ValueError(f"{d.name}: firmware {version} is below V{lowest}, the first that speaks Modbus RTU "
                             f"({evidence})")
    errata = MODBUS_ERRATA.get(d.name, {})
    used = set()
    absent: list[Item] = []
    for item in sorted(d.items, key=lambda i: i.row.address):
        row = item.row
        where = f"row {row.name}({row.address})"
        if row.modbus.upper() == NOT_MAPPED:
            item.absent_in = [MODBUS]
            absent.append(item)
            continue
        if not row.modbus:
            raise ValueError(f"{d.name}: {where} has no Modbus address (an elided row between numbered ones?)")
        expected = expected_cell(row.address, row.size)
        if same_cell(row.modbus, expected):
            continue
        erratum = errata.get(row.address)
        if erratum is None or not same_cell(row.modbus, erratum[0]):
            raise ValueError(f"{d.name}: {where}: Modbus Address '{row.modbus}' is not '{expected}' "
                             f"(40001 + floor(address / 2), Lo Byte at an even address, Hi Byte at an odd one)")
        used.add(row.address)
        item.notes.append(f"modbus: the page prints '{row.modbus}'; the map places the item at '{expected}': "
                          f"{erratum[1]}")
    stale = sorted(set(errata) - used)
    if stale:
        raise ValueError(f"{d.name}: decisions/modbus.py names rows at {stale} as misprinted, but the page "
                         f"prints them as the rule gives (or has no such row)")
    d.notes.append(f"modbus: Modbus RTU needs firmware V{lowest} or later, per {evidence}; firmware_version {fw} "
                   f"is that or later")
    if absent:
        d.notes.append(f"modbus: the page prints Modbus Address 'N/A' for {series_names(absent)}: they are "
                       f"absent_in modbus (not in the register map, and without effect while the servo speaks "
                       f"Modbus)")


def series_names(items: list[Item]) -> str:
    """'Return Delay Time(9), Indirect Address 1 ~ 128(168 ~ 422), ...': names with addresses, a
    numbered series as its range."""
    out: list[list] = []      # [base, first number, last number, first address, last address] or [name, address]
    for item in items:
        n = numbered(item.row.name)
        last = out[-1] if out else None
        if n and last and len(last) == 5 and last[0] == n[0] and last[2] + 1 == n[1]:
            last[2], last[4] = n[1], item.row.address
        elif n:
            out.append([n[0], n[1], n[1], item.row.address, item.row.address])
        else:
            out.append([item.row.name, item.row.address])
    parts = []
    for entry in out:
        if len(entry) == 2:
            parts.append(f"{entry[0]}({entry[1]})")
        elif entry[1] == entry[2]:
            parts.append(f"{entry[0]} {entry[1]}({entry[3]})")
        else:
            parts.append(f"{entry[0]} {entry[1]} ~ {entry[2]}({entry[3]} ~ {entry[4]})")
    return ", ".join(parts)
