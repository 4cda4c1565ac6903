"""One control-table page of the reference, parsed: the EEPROM and RAM tables (or the one
combined table of the DYNAMIXEL-Y pages, split by its Area column) as rows (elided '…' series
expanded), and the 'Control Table Description' sections with the addresses their headings name.

This is what the page prints, nothing decided: the builder turns it into a model.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

from .markdown import Table, camel_to_include, clean_cell, parse_int, tables_in
from .reference import TAG_ALIASES, Reference


@dataclass
class Row:
    """One control-table row as printed (after ellipsis expansion, `expanded` is True)."""
    address: int
    size: int
    name: str
    access: str
    initial: str
    range: str
    unit: str
    minmax: tuple | None      # XL-320 Min/Max columns
    area: str
    expanded: bool = False
    borrowed: str = ""        # the page the row was taken from, when this page's revision lacks it
    by_protocol: str = ""     # the Initial cell as printed, where it gives one value per protocol
    modbus: str = ""          # the Modbus Address cell as printed ('40004 (Hi Byte)', 'N/A'); "" without one


@dataclass
class Section:
    """A 'Control Table Description' section: its heading, addresses and text."""
    title: str
    addresses: list[int]
    start: int
    end: int


@dataclass
class Page:
    """A parsed page; `columns` are the meanings its table headers have (map_columns)."""
    name: str
    family: str
    group: str
    lines: list[str]
    rows: list[Row]
    sections: list[Section]
    columns: set
    modbus_only: list[str] = field(default_factory=list)   # rows of the Modbus map alone, dropped

    @property
    def text(self) -> str:
        """The whole page."""
        return "\n".join(self.lines)

    def section_for(self, address: int) -> list[Section]:
        """The description sections whose heading names `address`."""
        return [s for s in self.sections if address in s.addresses]

    def section_text(self, sec: Section, ref: Reference) -> str:
        """Section text with its include tags expanded (includes that were copied)."""
        chunk = "\n".join(self.lines[sec.start:sec.end])

        def expand_tag(m):
            inc = ref.include(TAG_ALIASES.get(camel_to_include(m.group(1)), camel_to_include(m.group(1))),
                              self.group)
            return inc if inc is not None else m.group(0)

        def expand_liquid(m):
            inc = ref.include(m.group(1), self.group)
            return inc if inc is not None else m.group(0)

        chunk = re.sub(r"<(ControlTable\w+)\s*/>", expand_tag, chunk)
        return re.sub(r"{%\s*include\s+en/dxl/([\w]+)\.md\s*%}", expand_liquid, chunk)


COLUMN_PATTERNS = [
    ("address", r"^address$"), ("size", r"^size"), ("name", r"^data name$"),
    ("description", r"^description$"), ("access", r"^access$"), ("initial", r"^(initial|default value)"),
    ("range", r"^range$"), ("unit", r"^unit$"), ("min", r"^min$"), ("max", r"^max$"),
    ("modbus", r"modbus"), ("area", r"^area$"),
]


def map_columns(header: list[str]) -> dict[str, int]:
    """Column index by meaning, located by header text (column sets differ between pages)."""
    cols = {}
    for idx, h in enumerate(header):
        for key, pat in COLUMN_PATTERNS:
            if re.search(pat, h.lower()) and key not in cols:
                cols[key] = idx
                break
    for needed in ("address", "size", "name", "access", "initial"):
        if needed not in cols:
            raise ValueError(f"control table header lacks {needed!r}: {header}")
    return cols


def control_tables(lines: list[str]) -> list[tuple[str, Table]]:
    """The EEPROM and RAM tables: first table after a 'Control Table of ... Area' heading. A page
    with one combined table (DYNAMIXEL-Y: 'Control Table Configuration', an Area column naming
    EEPROM, RAM or Hybrid per row) gives it once, with the area "" (read from the column)."""
    found = []
    for i, line in enumerate(lines):
        m = re.match(r"#+\s.*Control Table of (EEPROM|RAM) Area", line)
        combined = re.match(r"#+\s.*Control Table Configuration", line)
        if m or combined:
            tabs = tables_in(lines, i + 1, min(len(lines), i + 400))
            if not tabs:
                raise ValueError(f"no table after {line!r}")
            if combined and "area" not in map_columns(tabs[0].header):
                raise ValueError(f"the table after {line!r} has no Area column")
            found.append((m.group(1) if m else "", tabs[0]))
    return found


# The Area column's values, as the model format writes them.
AREAS = {"eeprom": "EEPROM", "ram": "RAM", "hybrid": "Hybrid"}


def protocol2_line(initial_raw: str, range_raw: str) -> tuple[str, str] | None:
    """(initial, range) of a cell pair that prints one line per protocol (DYNAMIXEL-Y: Initial
    '4,040<br />4,041<sup>1)</sup>', Range '4,040 (Dynamixel Protocol 2.0)<br />4,041 (Modbus)'):
    the initial of the Protocol 2.0 line, and the range as the list of every line's value (the
    item accepts them all); None where the cells are not split by protocol."""
    inits = re.split(r"<br\s*/?>", initial_raw)
    ranges = [clean_cell(r) for r in re.split(r"<br\s*/?>", range_raw)]
    if len(inits) < 2 or len(inits) != len(ranges):
        return None
    line = next((k for k, r in enumerate(ranges) if re.search(r"protocol 2\.0", r, re.I)), None)
    if line is None:
        return None
    values = [parse_int(re.sub(r"\s*\(.*\)\s*$", "", r)) for r in ranges]
    if None in values:
        raise ValueError(f"per-protocol range not understood: {range_raw!r}")
    initial = clean_cell(re.sub(r"<sup>.*?</sup>", "", inits[line]))    # the footnote mark is no digit
    return initial, ", ".join(str(v) for v in values)


def modbus_cell(text: str) -> str:
    """A cleaned Modbus Address cell without the emphasis some pages wrap it in ('*40001*')."""
    return re.sub(r"\s+", " ", text.replace("*", "")).strip()


def read_rows(area: str, table: Table) -> list[dict]:
    """The cells of each row by meaning, cleaned (ellipsis rows included, see expand_ellipses)."""
    cols = map_columns(table.header)
    out = []
    for cells, raw in zip(table.rows, table.raw_rows):
        if len(cells) < len(table.header):
            cells = cells + [""] * (len(table.header) - len(cells))

        def cell(key, raw_cell=False):
            if key not in cols:
                return ""
            return cells[cols[key]] if raw_cell else clean_cell(cells[cols[key]])

        row_area = area or AREAS.get(cell("area").lower(), cell("area"))
        if row_area not in AREAS.values() and parse_int(cell("address")) is not None:
            raise ValueError(f"unknown area {row_area!r}: {raw}")
        initial, rng = cell("initial"), cell("range")
        by_protocol = protocol2_line(cell("initial", raw_cell=True), cell("range", raw_cell=True))
        if by_protocol is not None:
            initial, rng = by_protocol
            if cell("access") == "R":
                rng = "-"        # a read-only item has no accepted values; its width applies
        out.append({
            "area": row_area, "address": cell("address"), "size": cell("size"), "name": cell("name"),
            "access": cell("access"), "initial": initial, "range": rng,
            "by_protocol": clean_cell(cells[cols["initial"]]) if by_protocol else "",
            "unit": clean_cell(re.sub(r"<br\s*/?>", " / ", cell("unit", raw_cell=True))) if "unit" in cols else "",
            "min": cell("min"), "max": cell("max"), "modbus": modbus_cell(cell("modbus")),
            "has_minmax": "min" in cols, "raw": raw,
        })
    return out


def is_ellipsis_row(r: dict) -> bool:
    """A row standing for an elided series: its Address cell is no number ('…')."""
    return parse_int(r["address"]) is None


def numbered(name: str) -> tuple[str, int] | None:
    """'Indirect Address 27' -> ('Indirect Address', 27); None without a trailing number."""
    m = re.fullmatch(r"(.*?)\s*(\d+)", name)
    return (m.group(1), int(m.group(2))) if m else None


def expand_ellipses(raw: list[dict]) -> list[Row]:
    """Replace '…' rows by the series they stand for, from the two rows before and the row after.

    Address step and initial-value step come from the two preceding rows; the row after the
    ellipsis must land exactly where the series predicts, otherwise the page is not understood.
    """
    rows: list[Row] = []

    def to_row(r: dict, expanded=False) -> Row:
        mm = None
        if r["has_minmax"]:
            mm = (r["min"], r["max"])
        return Row(parse_int(r["address"]), parse_int(r["size"]), r["name"], r["access"], r["initial"],
                   r["range"], r["unit"], mm, r["area"], expanded, by_protocol=r.get("by_protocol", ""),
                   modbus=r.get("modbus", ""))

    i = 0
    while i < len(raw):
        r = raw[i]
        if not is_ellipsis_row(r):
            row = to_row(r)
            if row.size is None:
                raise ValueError(f"row without a size: {r['raw']}")
            rows.append(row)
            i += 1
            continue
        if len(rows) < 2 or i + 1 >= len(raw):
            raise ValueError(f"ellipsis row without neighbours: {r['raw']}")
        prev2, prev, nxt = rows[-2], rows[-1], to_row(raw[i + 1])
        a, b, c = numbered(prev2.name), numbered(prev.name), numbered(nxt.name)
        if not (a and b and c) or not (a[0] == b[0] == c[0]) or b[1] != a[1] + 1:
            raise ValueError(f"cannot expand ellipsis between {prev.name!r} and {nxt.name!r}")
        base, count = b[0], c[1] - b[1] - 1
        step = prev.address - prev2.address
        init_a, init_b, init_c = parse_int(prev2.initial), parse_int(prev.initial), parse_int(nxt.initial)
        init_step = (init_b - init_a) if init_a is not None and init_b is not None else None
        if prev.address + step * (count + 1) != nxt.address:
            raise ValueError(f"ellipsis before {nxt.name}: address series does not reach {nxt.address}")
        if init_step is not None and init_c is not None and init_b + init_step * (count + 1) != init_c:
            raise ValueError(f"ellipsis before {nxt.name}: initial series does not reach {init_c}")
        # An elided row's Modbus address is known only where the series has none ('N/A' on both sides);
        # a numbered one is left unknown (""), which a page whose map is read refuses (modbus_map.py).
        modbus = prev.modbus if prev.modbus.upper() == nxt.modbus.upper() == "N/A" else ""
        for k in range(1, count + 1):
            initial = str(init_b + init_step * k) if init_step is not None else prev.initial
            rows.append(Row(prev.address + step * k, prev.size, f"{base} {b[1] + k}", prev.access, initial,
                            prev.range, prev.unit, prev.minmax, prev.area, expanded=True, modbus=modbus))
        i += 1
    return rows


HEADING_RE = re.compile(r"^(#{2,5})\s+(.*)$")


def description_sections(lines: list[str]) -> list[Section]:
    """Sections below 'Control Table Description', with the addresses named in their heading."""
    start = next((i for i, l in enumerate(lines) if re.match(r"#+\s.*Control Table Description", l)), None)
    if start is None:
        return []
    heads = []
    for i in range(start + 1, len(lines)):
        m = HEADING_RE.match(lines[i])
        if m:
            heads.append((i, clean_cell(m.group(2))))
    sections = []
    for n, (i, title) in enumerate(heads):
        end = heads[n + 1][0] if n + 1 < len(heads) else len(lines)
        addrs = []
        for group in re.findall(r"\(([\d,\s]+)\)", title):
            addrs += [int(x) for x in re.findall(r"\d+", group)]
        sections.append(Section(title, addrs, i + 1, end))
    return sections


def borrow_rows(page: Page, donor: Page, names: tuple[str, ...]) -> None:
    """Adds the rows `names` of `donor` to `page` (marked `borrowed`), in address order: rows an
    older revision of a page lacks that a newer page of the same table has."""
    for name in names:
        rows = [r for r in donor.rows if r.name == name]
        if len(rows) != 1:
            raise ValueError(f"{page.name}: {donor.name} has no single row {name!r} to borrow")
        if any(r.address == rows[0].address for r in page.rows):
            raise ValueError(f"{page.name}: address {rows[0].address} of {name!r} is taken")
        page.rows.append(replace(rows[0], borrowed=donor.name))
    page.rows.sort(key=lambda r: r.address)


def read_page(ref: Reference, name: str, family: str, group: str) -> Page:
    """control-tables/<name>.md parsed; `family` and `group` (the e-Manual product group, which
    picks the Liquid branches of its includes) come from decisions/catalogue.py."""
    lines = ref.text(f"control-tables/{name}.md").splitlines()
    raw, columns = [], set()
    tabs = control_tables(lines)
    if [a for a, _ in tabs] not in (["EEPROM", "RAM"], [""]):
        raise ValueError(f"{name}: expected an EEPROM and a RAM table or one combined table, "
                         f"found {[a or 'combined' for a, _ in tabs]}")
    for area, table in tabs:
        columns |= set(map_columns(table.header))
        raw += read_rows(area, table)
    # Rows with no DYNAMIXEL address (Address 'N/A') exist only in the Modbus map (DYNAMIXEL-Y's
    # instruction registers): they are no control-table items (the builder notes them).
    modbus_only = [r["name"] for r in raw if r["address"].upper() == "N/A"]
    raw = [r for r in raw if r["address"].upper() != "N/A"]
    rows = expand_ellipses(raw)
    return Page(name, family, group, lines, rows, description_sections(lines), columns, modbus_only)
