"""The e-Manual's Markdown, read generically: pipe tables, the plain text of a cell, numbers,
units and bit rates as the pages print them, keys from names, and Liquid `product_group` branches.

Nothing here knows a model or a family; page.py and the builder use these to read pages.
"""

from __future__ import annotations

import html
import re
from dataclasses import dataclass

ELLIPSES = {"…", "...", "···", "..", "⋯"}


def clean_cell(text: str) -> str:
    """Plain text of a table cell: links, HTML, entities, emphasis and escapes removed."""
    t = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)         # [Name](#anchor) -> Name
    t = re.sub(r"<br\s*/?>", " ", t, flags=re.I)
    t = re.sub(r"<sup>(.*?)</sup>", lambda m: {"2": "²"}.get(m.group(1), m.group(1)), t)
    t = re.sub(r"<[^>]+>", "", t)
    t = html.unescape(t)
    t = t.replace("\\", "").replace("**", "").replace("`", "")
    t = re.sub(r"(?<!\w)_(.+?)_(?!\w)", r"\1", t)                # _Modbus_ -> Modbus
    return re.sub(r"\s+", " ", t).strip()


def split_row(line: str) -> list[str]:
    """The raw cells of a pipe-table line (outer pipes dropped)."""
    body = line.strip()
    if body.startswith("|"):
        body = body[1:]
    if body.endswith("|"):
        body = body[:-1]
    return [c for c in body.split("|")]


def is_separator(cells: list[str]) -> bool:
    """True for the '|---|:--:|' line under a table header."""
    return all(re.fullmatch(r"\s*:?-{2,}:?\s*", c or "") for c in cells)


@dataclass
class Table:
    """A pipe table: cleaned header, raw cells per row."""
    line: int                 # 0-based line of the header
    header: list[str]         # cleaned header cells
    rows: list[list[str]]     # raw cells (uncleaned) of each data row
    raw_rows: list[str]


def tables_in(lines: list[str], start: int = 0, end: int | None = None) -> list[Table]:
    """Markdown pipe tables between two line numbers."""
    end = len(lines) if end is None else end
    out, i = [], start
    while i < end - 1:
        if lines[i].lstrip().startswith("|") and is_separator(split_row(lines[i + 1])):
            header = [clean_cell(c) for c in split_row(lines[i])]
            rows, raws, j = [], [], i + 2
            while j < end and lines[j].lstrip().startswith("|"):
                rows.append(split_row(lines[j]))
                raws.append(lines[j])
                j += 1
            out.append(Table(i, header, rows, raws))
            i = j
        else:
            i += 1
    return out


def parse_int(text: str) -> int | None:
    """'1,044,479' / '-501,923' / ' 250 ' -> int; anything else -> None."""
    t = text.strip().replace("−", "-")
    if re.fullmatch(r"-?\d{1,3}(,\d{3})+", t):      # thousands separators only in groups of three
        t = t.replace(",", "")
    return int(t) if re.fullmatch(r"-?\d+", t) else None


def norm_space(text: str) -> str:
    """Runs of whitespace as one space, ends stripped."""
    return re.sub(r"\s+", " ", text).strip()


def snake_key(name: str) -> str:
    """key = snake_case of the e-Manual name; parenthesised parts dropped."""
    t = re.sub(r"\([^)]*\)", "", name).lower()
    t = re.sub(r"[^a-z0-9]+", "_", t)
    return t.strip("_")


def camel_to_include(tag: str) -> str:
    """<ControlTableOpmodeSix2 /> -> control_table_opmode_six_2 (includes/README naming rule)."""
    parts = re.findall(r"[A-Z][a-z]*|\d+", tag)
    return "_".join(p.lower() for p in parts)


def select_liquid_branch(text: str, group: str) -> str:
    """Keep only the branch of top-level {% if page.product_group==... %} blocks that applies."""
    out, pos = [], 0
    pattern = re.compile(r"{%\s*(if|elsif|else|endif)\b(.*?)%}", re.S)
    depth, taking, taken = 0, True, False
    for m in pattern.finditer(text):
        kind, cond = m.group(1), m.group(2)
        if kind == "if":
            depth += 1
            if depth > 1:
                continue
            if taking:
                out.append(text[pos:m.start()])
            groups = re.findall(r"product_group\s*==\s*'([^']+)'", cond)
            negated = re.findall(r"product_group\s*!=\s*'([^']+)'", cond)
            taken = (group in groups) if groups else (group not in negated if negated else True)
            taking, pos = taken, m.end()
        elif depth == 1 and kind in ("elsif", "else"):
            if taking:
                out.append(text[pos:m.start()])
            if kind == "elsif":
                groups = re.findall(r"product_group\s*==\s*'([^']+)'", cond)
                taking = (not taken) and group in groups
            else:
                taking = not taken
            taken = taken or taking
            pos = m.end()
        elif kind == "endif":
            if depth == 1:
                if taking:
                    out.append(text[pos:m.start()])
                taking, pos = True, m.end()
            depth -= 1
    out.append(text[pos:])
    return "".join(out)


def clean_unit(unit: str) -> str | None:
    """A Unit cell as the model stores it ('[ V ]' -> '[V]'); None for '-', empty or an ellipsis."""
    u = norm_space(unit.replace("[ ", "[").replace(" ]", "]"))
    u = re.sub(r"\s+\]", "]", u)
    return None if u in ("", "-") or u in ELLIPSES else u


def unit_number(unit: str | None) -> float | None:
    """The leading figure of a unit ('about 0.229 [rev/min]' -> 0.229); None without one."""
    if not unit:
        return None
    m = re.match(r"(?:about\s*)?([\d.]+)", unit.strip(), re.I)
    return float(m.group(1)) if m else None


def parse_bps(text: str) -> int | None:
    """A baud-table cell as bits per second ('57,600', '1M', '4.5 Mbps'); None when it is not one."""
    t = text.replace("[bps]", "").replace("bps", "").replace(",", "").strip()
    m = re.fullmatch(r"([\d.]+)\s*(M|Mbps|K)?", t.replace(" ", ""))
    if not m:
        return None
    n = float(m.group(1))
    mult = {"M": 1e6, "Mbps": 1e6, "K": 1e3, None: 1}[m.group(2)]
    return int(round(n * mult))
