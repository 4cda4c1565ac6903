"""The tables of one FEETECH reference file (../shared/reference/feetech/<model>.md), as printed:
FEETECH's wiki memory table (Table A) with the section of each row, the ST3215 spreadsheet export
where the file has one, and lerobot's control table where it has one."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from model_converter.markdown import clean_cell, parse_int, tables_in

# The wiki's section headings ("##### 2.2 EPROM Configuration") and where their items live.
SECTION_AREAS = {
    "Version Information": "EEPROM",
    "EPROM Configuration": "EEPROM",
    "SRAM Control": "RAM",
    "SRAM Feedback": "RAM",
    "Factory Parameters": "EEPROM",
}


@dataclass
class WikiRow:
    """One row of FEETECH's memory table, its cells cleaned but not interpreted."""
    address: str
    function: str
    size: str
    initial: str
    access: str
    range: str
    unit: str
    description: str
    section: str


@dataclass
class SheetRow:
    """One row of the ST3215 spreadsheet export."""
    address: int
    function: str
    size: int
    initial: int | None
    minimum: int | None
    maximum: int | None


@dataclass
class LerobotEntry:
    """One entry of lerobot's control table."""
    name: str
    address: int
    size: int


@dataclass
class FeetechReference:
    """What the converter reads of one reference file."""
    path: Path
    wiki: list[WikiRow]
    sheet: list[SheetRow]
    lerobot: list[LerobotEntry]


def part(lines: list[str], title_start: str) -> tuple[int, int] | None:
    """The line span of the '## ' part whose title starts with `title_start`."""
    starts = [i for i, line in enumerate(lines) if line.startswith("## ")]
    for n, i in enumerate(starts):
        if lines[i][3:].startswith(title_start):
            return i, starts[n + 1] if n + 1 < len(starts) else len(lines)
    return None


def wiki_rows(lines: list[str], span: tuple[int, int]) -> list[WikiRow]:
    """The rows of every table of the wiki part, with the section heading above each table."""
    rows: list[WikiRow] = []
    for table in tables_in(lines, *span):
        if not table.header or table.header[0] != "Address (DEC)":
            continue
        heading = next(lines[i] for i in range(table.line, span[0] - 1, -1) if lines[i].startswith("#####"))
        section = re.sub(r"^#+\s*[\d.]+\s*", "", heading).strip()
        if section not in SECTION_AREAS:
            raise ValueError(f"unknown section {section!r} above line {table.line + 1}")
        for cells in table.rows:
            c = [clean_cell(x) for x in cells]
            if len(c) != 9:
                raise ValueError(f"a memory-table row with {len(c)} cells: {cells}")
            rows.append(WikiRow(c[0], c[2], c[3], c[4], c[5], c[6], c[7], c[8], section))
    if not rows:
        raise ValueError("no FEETECH memory table")
    return rows


def sheet_rows(lines: list[str], span: tuple[int, int]) -> list[SheetRow]:
    """The spreadsheet's rows with a decimal address (its second header row has none); -1 in its
    minimum/maximum columns means none."""
    out = []
    for table in tables_in(lines, *span):
        for cells in table.rows:
            c = [clean_cell(x) for x in cells]
            address = parse_int(c[0])
            if address is None:
                continue
            def bound(text: str) -> int | None:
                value = parse_int(text)
                return None if value == -1 else value
            out.append(SheetRow(address, c[2], int(c[3]), parse_int(c[4]), bound(c[7]), bound(c[8])))
    return out


def lerobot_entries(lines: list[str], span: tuple[int, int]) -> list[LerobotEntry]:
    """lerobot's `data_name` and `(address, size_byte)` cells."""
    out = []
    for table in tables_in(lines, *span):
        if "data_name" not in table.header:
            continue
        for cells in table.rows:
            c = [clean_cell(x) for x in cells]
            found = re.search(r"\((\d+), (\d+)\)", c[2])
            if not found:
                raise ValueError(f"lerobot entry without (address, size): {cells}")
            out.append(LerobotEntry(c[1].strip(), int(found.group(1)), int(found.group(2))))
    return out


def read_reference(path: Path) -> FeetechReference:
    """The tables of the reference file at `path`; refuses a file without FEETECH's table."""
    lines = path.read_text(encoding="utf-8").splitlines()
    wiki = part(lines, "Table A")
    if wiki is None:
        raise ValueError(f"{path.name}: no 'Table A' part (FEETECH's memory table)")
    sheet = part(lines, "Table B — ST3215 spreadsheet")
    lerobot = next((s for s in (part(lines, "Table B — lerobot"), part(lines, "Table C — lerobot")) if s), None)
    try:
        return FeetechReference(path, wiki_rows(lines, wiki), sheet_rows(lines, sheet) if sheet else [],
                                lerobot_entries(lines, lerobot) if lerobot else [])
    except ValueError as exc:
        raise ValueError(f"{path.name}: {exc}") from exc
