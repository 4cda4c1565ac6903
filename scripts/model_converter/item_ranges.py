"""Where each item's range comes from, in order: the table's Range (or Min/Max) cell; else a
range table in the item's description section; else a documented choice (range_choices.py,
its evidence checked); else, on MX(2.0) pages, the same item on an X page; else the item's full
width. Then the bounds named by other items, and the few ranges widened so that the factory
value is accepted. Every choice leaves a "range: ..." note on the item.
"""

from __future__ import annotations

import re

from .decisions.item_rules import (LIMIT_MAX_OVERRIDES, NAME_ALIASES, RANGE_DONORS, WIDEN_TO_FACTORY,
                                   WIDEN_TO_FACTORY_BY_FAMILY)
from .decisions.model_fields import PROTOCOLS
from .decisions.range_choices import RANGE_CHOICES
from .items import Draft, Item
from .markdown import clean_cell, norm_space, parse_int, snake_key, tables_in
from .page import Row
from .ranges import RangeChoice, RangeSpec, bound_keys, evidence_found, find_choice, parse_range


def section_ranges(d: Draft, item: Item) -> list[RangeSpec]:
    """Ranges stated in small 'Unit | Value Range' tables of the item's description section."""
    out = []
    for sec in d.page.section_for(item.row.address):
        for tab in tables_in(d.page.section_text(sec, d.ref).splitlines()):
            # 'Unit | Value Range' / 'Unit | Range' tables; mode and bit tables have no such column
            idx = next((k for k, h in enumerate(tab.header) if "range" in h.lower()), None)
            if idx is None:
                continue
            for cells in tab.rows:
                if idx < len(cells):
                    try:
                        spec = parse_range(cells[idx])
                    except ValueError:
                        continue
                    if spec and (spec.min is not None or spec.lo_ref):
                        out.append(spec)
    return out


def choice_for(d: Draft, key: str) -> RangeChoice | None:
    """The documented choice for `key` in this family; its evidence must be where it says."""
    choice = find_choice(RANGE_CHOICES, d.lineage, key)
    if choice is not None and not evidence_found(choice, d.page.text, d.ref.text):
        raise SystemExit(f"convert_models: {d.name}.{key}: evidence {choice.quotes!r} "
                         f"not found in {choice.evidence}")
    return choice


def donor_range(d: Draft, row: Row) -> tuple[str, str, str] | None:
    """Range cell of the same item on a donor page (RANGE_DONORS; MX(2.0) pages have no Range
    column and borrow from the X pages).

    The MX(2.0) and X pages describe these items with the same shared include blocks, and the
    X tables print the ranges those blocks state. The donor item must have the same address,
    size and name.
    """
    want = NAME_ALIASES.get(row.name.lower(), row.name.lower())
    for dname, donor in d.donors.items():
        for drow in donor.rows:
            if drow.address == row.address and drow.size == row.size and \
                    NAME_ALIASES.get(drow.name.lower(), drow.name.lower()) == want and \
                    parse_range(drow.range) is not None:
                return dname, drow.range, drow.unit
    return None


def ref_key(d: Draft, ref: tuple, item: Item) -> tuple[str, Item]:
    """The key (with "-" when negated) of the item a Range cell names as a bound."""
    negated, name, addr = ref
    target = d.by_addr.get(addr)
    if target is None or snake_key(target.row.name) not in bound_keys(name):
        raise ValueError(f"{d.name}.{item.key}: range names {name}({addr}), which is not an item")
    return ("-" if negated else "") + target.key, target


def apply_spec(d: Draft, item: Item, spec: RangeSpec, source: str):
    """Set min/max/values/limits of `item` from a parsed Range cell."""
    key = item.key
    if spec.values is not None and len(spec.values) == 1 and spec.min is None:
        # Startup Configuration prints '3': the mask of its two defined bits.
        item.min, item.max = 0, spec.values[0]
        item.notes.append(f"range: {source} prints '{spec.raw}'; read as the bit mask of bits 0 ~ 1 "
                          f"(bit0 Startup Torque On, bit1 RAM Restore; bits 2 ~ 7 'Unused, always 0' "
                          f"per the Startup Configuration include), i.e. 0 ~ {spec.values[0]}")
        return
    if spec.values is not None:
        item.values = spec.values
        return
    item.min, item.max = spec.min, spec.max
    if spec.extra:
        if key == "profile_acceleration":
            lo2, hi2 = spec.extra[0]
            item.notes.append(f"range: {source} prints '{spec.raw}' (velocity-based profile 0 ~ {spec.max:,}, "
                              f"time-based profile 0 ~ {hi2:,} ms, Drive Mode bit 2); the static range is the "
                              f"wider velocity-based one; in time-based mode the emulator must also refuse "
                              f"values above {hi2:,} and cap acceleration time at 50% of Profile Velocity")
            item.max = max(spec.max, hi2)
        elif re.search(r"\(modbus\)", spec.raw, re.I):
            item.notes.append(modbus_range_note(d, source, spec))
        else:
            item.notes.append(f"range: {source} prints '{spec.raw}'; the first range (DYNAMIXEL Protocol "
                              f"2.0) is used, the other applies to a protocol dxlemu does not emulate")
    for side in ("lo", "hi"):
        ref = getattr(spec, f"{side}_ref")
        if ref:
            k, target = ref_key(d, ref, item)
            setattr(item, "limit_min" if side == "lo" else "limit_max", k)


def modbus_range_note(d: Draft, source: str, spec: RangeSpec) -> str:
    """The note on a Range cell with a second range for Modbus (ID: '1 ~ 247 (Modbus)'): the item
    keeps the Protocol 2.0 range; over Modbus the protocol's own ID range applies (its row in the
    protocol table), where the model speaks Modbus at all."""
    lo, hi = spec.extra[0]
    head = f"range: {source} prints '{spec.raw}'; the first range (DYNAMIXEL Protocol 2.0) is the item's"
    if "modbus" in d.lookup(PROTOCOLS)[0]:
        return (f"{head}; the Modbus range is enforced by the protocol (ID {lo} ~ {hi} over Modbus; another value "
                f"written over Modbus is refused with exception 03)")
    return f"{head}; the other is for Modbus RTU, which this model does not speak in dxlemu (see the protocols note)"


def printed_ranges(d: Draft):
    """Ranges from the table: the Range cell, or the Min/Max columns (XL-320)."""
    for item in d.items:
        row = item.row
        spec = None
        if row.minmax is not None:       # XL-320: Min / Max columns
            lo, hi = (parse_int(x) for x in row.minmax)
            if lo is not None and hi is not None:
                spec = RangeSpec(min=lo, max=hi, raw=f"{row.minmax[0]} ~ {row.minmax[1]}")
        elif "range" in d.page.columns:
            spec = parse_range(row.range)
        if spec is not None:
            item.range_from = "table"
            apply_spec(d, item, spec, "the table")


def fill_unprinted_ranges(d: Draft):
    """Ranges of the items the table leaves open, in the order of the module docstring."""
    for item in d.items:
        if item.range_from:
            continue
        # 1. a small range table in the item's own description section
        specs = section_ranges(d, item)
        if specs:
            apply_spec(d, item, specs[0], "its description section")
            item.range_from = "description"
            title = d.page.section_for(item.row.address)[0].title
            item.notes.append(f"range: the table has no range for this item; '{specs[0].raw}' is stated "
                              f"in the description section '{title}' (with its include blocks)")
            continue
        # 2. a documented choice with its evidence
        choice = choice_for(d, item.key)
        if choice:
            item.range_from = "choice"
            if choice.min is None:
                item.notes.append(f"range: {choice.note}")
                continue
            item.min, item.max = choice.min, choice.max
            item.signed = item.signed or choice.signed
            where = choice.evidence if choice.evidence != "PAGE" else "this page"
            quote = norm_space(clean_cell(choice.quotes[0]).replace("|", " ")) if choice.quotes else ""
            if quote and choice.evidence != "PAGE":
                where = f"{choice.evidence} ('{quote}')"
            elif quote:
                where = f"this page ('{quote}')"
            text = f"range: the page has no Range column; {choice.min} ~ {choice.max} from {where}"
            if choice.note:
                text += f"; {choice.note}"
            item.notes.append(text)
            continue
        # 3. the same item on a donor page (MX(2.0): the X pages)
        if d.is_in(RANGE_DONORS):
            donor = donor_range(d, item.row)
            if donor:
                dname, cell, _ = donor
                apply_spec(d, item, parse_range(cell), f"the {dname} table")
                item.range_from = "donor"
                label = d.lookup(RANGE_DONORS).label
                item.notes.append(f"range: the {label} page has no Range column; '{clean_cell(cell)}' is taken "
                                  f"from the same item in control-tables/{dname}.md, whose description uses the "
                                  f"same shared include block")
                continue
        # 4. nothing stated: the full width of the item (the format's default)
        item.range_from = "default"
        why = "read-only, " if item.access == "R" else ""
        item.notes.append(f"range: {why}no range printed or described; the full width of the item "
                          f"(format default) applies")


def resolve_limits(d: Draft):
    """Static min/max of items bounded by other items: the bounding item's own static range."""
    for item in d.items:
        for side in ("limit_min", "limit_max"):
            ref = getattr(item, side)
            if not ref:
                continue
            target = d.by_key[ref.lstrip("-")]
            lo, hi = target.static_range()
            if ref.startswith("-"):
                bound = -hi
            else:
                bound = lo if side == "limit_min" else hi
            if side == "limit_min" and item.min is None:
                item.min = bound
            if side == "limit_max" and item.max is None:
                item.max = bound
        if item.min is not None and item.min < 0:
            item.signed = True      # e.g. P/PRO Goal Position between negative position limits
        if item.limit_min or item.limit_max:
            item.notes.append(f"range: bounded by {item.limit_min or item.min} ~ {item.limit_max or item.max}; "
                              f"the static min/max ({item.min} ~ {item.max}) are the bounding items' own "
                              f"static range")
    for item in d.items:
        if item.min is not None and item.max is None or item.max is not None and item.min is None:
            raise ValueError(f"{d.name}.{item.key}: half a range")


def widen_to_factory(d: Draft):
    """Items printed with a range that excludes their factory value (WIDEN_TO_FACTORY)."""
    for key, (widest, note) in (WIDEN_TO_FACTORY | d.lookup(WIDEN_TO_FACTORY_BY_FAMILY, {})).items():
        item = d.by_key.get(key)
        if item is None or item.max is None or item.initial <= item.max:
            continue
        item.notes.append(note.format(min=item.min, max=item.max, initial=item.initial))
        item.max = widest


def limit_max_overrides(d: Draft):
    """Bounds the tables do not print (LIMIT_MAX_OVERRIDES): the static max is the lower one."""
    for key, bound, note in d.lookup(LIMIT_MAX_OVERRIDES, ()):
        item, lim = d.by_key[key], d.by_key[bound]
        item.limit_max = bound
        item.notes.append(note)
        item.max = min(item.max, lim.max)


def check_description_agreement(d: Draft):
    """Where both the table and a description table state a range, record disagreements."""
    for item in d.items:
        if item.range_from != "table":
            continue
        for spec in section_ranges(d, item):
            if spec.min is not None and spec.max is not None and (spec.min, spec.max) != (item.min, item.max) \
                    and not spec.extra and len(d.page.section_for(item.row.address)) == 1:
                sec = d.page.section_for(item.row.address)[0]
                if len(sec.addresses) == 1:
                    item.notes.append(f"range: the table's {item.min} ~ {item.max} is used; the description "
                                      f"section says '{spec.raw}' (the page disagrees with itself)")
