"""One page to one model dict: the items (item_builder.py), then the model-level fields (baud
table, timing, protocols, motion, indirect blocks, dual axis) with a note for every choice."""

from __future__ import annotations

import re

from . import motion
from .decisions.model_fields import (BAUD_FORMULA_FAMILIES, BAUD_FORMULA_NOTE, BOOT_MS, BOOT_NOTE, DEFAULT_ID,
                                     DUAL_AXIS, EXTERNAL_BAUD, FIRMWARE, INDIRECT_BLOCKS, OLDER_FIRMWARE_NOTE, PROTOCOLS,
                                     SHARED_MODEL_NUMBERS, RETURN_DELAY_NOTE, RETURN_DELAY_UNIT_US, TIMING)
from .firmware import firmware_needs, older_indirect
from .item_builder import build_items
from .items import Draft
from .markdown import clean_cell, parse_bps, tables_in
from .modbus_map import MODBUS, read_modbus_map
from .decisions.catalogue import classify
from .page import Page, read_page
from .reference import Reference


def build_model(ref: Reference, page: Page, donors: dict[str, Page]) -> dict:
    """The model dict of `page`; `donors` are the pages its missing ranges are read from
    (item_rules.RANGE_DONORS)."""
    d = Draft(ref, page, donors)
    fw, fw_note = d.lookup(FIRMWARE)
    build_items(d, fw)

    model_number = d.by_key["model_number"].initial
    # models.tsv gives '4040 (Protocol 2.0); 4041 (Modbus)' where the page prints both numbers
    tsv_number = re.sub(r"\s*\(Protocol 2\.0\);.*$", "", d.tsv["model_number"])
    if str(model_number) != tsv_number:
        raise ValueError(f"{d.name}: model number {model_number} != models.tsv {d.tsv['model_number']}")
    d.notes.insert(0, fw_note)
    if d.page.modbus_only:
        d.notes.append(f"items: the page's table also lists {', '.join(d.page.modbus_only)} with Address "
                       "'N/A' and a Modbus address only: registers of the Modbus map, no control-table items, and "
                       "this model does not speak Modbus RTU in dxlemu (see the protocols note), so they are left out")
    rates, default_baud = baud_rates(d)
    figures, timing_note = d.lookup(TIMING)
    d.notes += [timing_note, BOOT_NOTE, RETURN_DELAY_NOTE]
    dual = DUAL_AXIS.get(d.name)
    if dual:
        d.notes.append(dual.default_id_note)
    model = {"name": d.name, "title": title(d), "model_number": model_number}
    shared = SHARED_MODEL_NUMBERS.get(d.name)
    if shared:
        model["shares_model_number_with"] = shared[0]
        d.notes.append(shared[1])
    model |= {
        "firmware_version": fw, "family": d.family, "protocols": protocols(d),
        "default_id": DEFAULT_ID, "baud_rates": rates, "default_baud_index": default_baud,
        "return_delay_unit_us": RETURN_DELAY_UNIT_US, "timing": dict(figures, boot_ms=BOOT_MS),
        "motion": motion.motion(d),
    }
    ind = indirect(d)
    if ind:
        model["indirect"] = ind
    variants = firmware_variants(d, fw)
    if variants:
        model["firmware_variants"] = variants
    if MODBUS in model["protocols"]:
        read_modbus_map(d, fw, [v["firmware_version"] for v in variants or []])
    if dual:
        model["axes"] = 2
        model["shared_items"] = list(dual.shared_items)
        d.notes.append(dual.note)
    model["source"] = source(d)
    model["notes"] = d.notes
    model["items"] = [i.to_json() for i in sorted(d.items, key=lambda i: i.row.address)]
    return model


def baud_rates(d: Draft) -> tuple[list[dict], int]:
    """The baud table (the page's Baud Rate section, else EXTERNAL_BAUD) and the default index."""
    if d.is_in(EXTERNAL_BAUD):
        table, url = d.lookup(EXTERNAL_BAUD)
        d.notes.append(f"baud_rates: the page's Baud Rate include is not in the reference; the table is "
                       f"from {url} (nominal rates)")
        rates = table
    else:
        rates = parse_baud_tables(d)
    default = d.by_key["baud_rate"].initial
    if d.is_in(BAUD_FORMULA_FAMILIES):
        d.notes.append(BAUD_FORMULA_NOTE)
    return [{"index": i, "bps": b} for i, b in sorted(rates)], default


def parse_baud_tables(d: Draft) -> list[tuple[int, int]]:
    """The (index, bps) rows of the Value tables in the page's Baud Rate section."""
    secs = [s for s in d.page.sections if "baud rate" in s.title.lower()]
    if not secs:
        raise ValueError(f"{d.name}: no Baud Rate section")
    text = d.page.section_text(secs[0], d.ref)
    rates = {}
    for tab in tables_in(text.splitlines()):
        if not tab.header or tab.header[0].lower() != "value":
            continue
        bcol = next(i for i, h in enumerate(tab.header) if "baud" in h.lower())
        for cells in tab.rows:
            idx = re.match(r"\s*(\d+)", clean_cell(cells[0]))
            bps = parse_bps(clean_cell(cells[bcol]))
            if idx and bps:
                rates[int(idx.group(1))] = bps
    if not rates:
        raise ValueError(f"{d.name}: no baud table found")
    return list(rates.items())


def indirect(d: Draft) -> list[dict] | None:
    """The Indirect Address / Data blocks (INDIRECT_BLOCKS), checked against the items; None without any."""
    ind = [i for i in d.items if i.key.startswith("indirect_")]
    if not ind:
        return None
    blocks = d.lookup(INDIRECT_BLOCKS)
    expected = set()
    out = []
    for first, last, addr0, data0 in blocks:
        for n in range(first, last + 1):
            a = d.by_key.get(f"indirect_address_{n}")
            data = d.by_key.get(f"indirect_data_{n}")
            if not a or a.row.address != addr0 + 2 * (n - first) or a.row.size != 2:
                raise ValueError(f"{d.name}: Indirect Address {n} not at {addr0 + 2 * (n - first)}")
            if not data or data.row.address != data0 + (n - first) or data.row.size != 1:
                raise ValueError(f"{d.name}: Indirect Data {n} not at {data0 + (n - first)}")
            expected |= {a.key, data.key}
        out.append({"address": addr0, "data": data0, "count": last - first + 1})
    extra = {i.key for i in ind} - expected
    if extra:
        raise ValueError(f"{d.name}: indirect items outside the expected blocks: {sorted(extra)}")
    d.notes.append("indirect: " + ", ".join(
        f"Indirect Address {f} ~ {l} at {a} ~ {a + 2 * (l - f)}, Data at {data} ~ {data + (l - f)}"
        for f, l, a, data in blocks) + " (elided rows expanded; counts match the page and README)")
    return out


def page_needs(d: Draft) -> list:
    """The firmware needs of the page, and of the pages its borrowed rows come from (for those rows)."""
    needs = firmware_needs(d.ref, d.page)
    for donor in sorted({r.borrowed for r in d.page.rows if r.borrowed}):
        rows = {r.address for r in d.page.rows if r.borrowed == donor}
        needs += [n for n in firmware_needs(d.ref, read_page(d.ref, donor, *classify(donor)))
                  if rows & set(n.addresses)]
    return needs


def check_firmware(d: Draft, fw: int) -> None:
    """Refuses a firmware below a version the page (or a donor of its rows) asks for an item the
    model has."""
    for need in page_needs(d):
        if need.version > fw and any(a in d.by_addr for a in need.addresses):
            raise ValueError(f"{d.name}: firmware_version {fw} is below v{need.version}, which {need.section} "
                             f"needs ('{need.quote}')")
    older = older_indirect(d.page)
    if older and fw < older.before:
        raise ValueError(f"{d.name}: firmware_version {fw} serves the Indirect blocks of V{older.before} or later "
                         f"('{older.quote}')")


def firmware_variants(d: Draft, fw: int) -> list[dict] | None:
    """The older firmware the page's note describes (firmware.older_indirect), as a variant of the
    model: its version and its Indirect blocks, the only part of the table that differs."""
    check_firmware(d, fw)
    older = older_indirect(d.page)
    if older is None:
        return None
    version = older.before - 1
    for need in page_needs(d):
        if need.version > version and any(a in d.by_addr for a in need.addresses):
            raise ValueError(f"{d.name}: the firmware {version} variant lacks {need.section} ('{need.quote}')")
    first = d.by_key.get("indirect_address_1")
    if first is None or first.row.address != older.address:
        raise ValueError(f"{d.name}: the older Indirect blocks start at {older.address}, the table's do not")
    note = OLDER_FIRMWARE_NOTE.format(version=version, quote=older.quote, before=older.before, count=older.count,
                                      address=older.address, address_end=older.address + 2 * older.count - 1,
                                      data=older.data, data_end=older.data + older.count - 1)
    return [{"firmware_version": version,
             "indirect": [{"address": older.address, "data": older.data, "count": older.count}],
             "notes": [note]}]


def protocols(d: Draft) -> list:
    """The protocols the model speaks (PROTOCOLS)."""
    listed, note = d.lookup(PROTOCOLS)
    if note:
        d.notes.append(note)
    return list(listed)


def source(d: Draft) -> str:
    """The page and the e-Manual file (and commit) its header names."""
    head = "\n".join(d.page.lines[:15])
    m = re.search(r"(?:Text below taken from|e-Manual source):\s*(ROBOTIS-GIT/\w+) `([^`]+)`"
                  r"(?:[^\n]*?(?:commit|@) ([0-9a-f]{40}))?", head)
    if not m:
        raise ValueError(f"{d.name}: page header names no source")
    src = f"{m.group(1)} {m.group(2)}"
    if m.group(3):
        src += f" @ {m.group(3)}"
    return f"control-tables/{d.name}.md ({src})"


def title(d: Draft) -> str:
    """models.tsv's model name as ROBOTIS prints it ('MX-28', 'MX-28(2.0)', 'H54-200-S500-R')."""
    t = d.tsv["model"]
    if "(1.0)" in t or "(legacy PRO)" in t:
        t = t.replace(" (legacy PRO)", "").replace("(1.0)", "")
        d.notes.append(f"title: '{t}' as the page prints it; models.tsv's '{d.tsv['model']}' adds a "
                       f"qualifier that the name field already carries")
    return t
