"""A page's Specifications table: no-load speed, stall torque and current, and the voltage they
are stated at (the X pages print one; most others were not copied)."""

from __future__ import annotations

import re
from dataclasses import dataclass

from .markdown import clean_cell, tables_in


@dataclass
class PageSpec:
    """Motor figures read from a page's Specifications table (see parse_spec_table)."""
    rpm: float
    nm: float
    amps: float | None
    volts: float | None
    detail: str
    torque_text: str
    speed_text: str


def parse_spec_table(lines: list[str]) -> PageSpec | None:
    """No-load speed, stall torque and stall current, and the voltage they are stated at, from a
    Specifications table; where several voltages are listed, the recommended one."""
    rows = {}
    for tab in tables_in(lines):
        if tab.header and tab.header[0].lower().startswith("item"):
            for cells in tab.rows:
                if len(cells) >= 2:
                    rows[clean_cell(cells[0]).lower()] = cells[1]
    if "stall torque" not in rows or "no load speed" not in rows:
        return None
    rec = re.search(r"Recommended\s*:\s*([\d.]+)", clean_cell(rows.get("input voltage", "")))
    rec_v = float(rec.group(1)) if rec else None

    def entries(cell):
        out = []
        for part in re.split(r"<br\s*/?>", cell):
            p = clean_cell(part)
            num = re.match(r"\s*([\d.]+)", p)
            volt = re.search(r"(?:at|@)\s*([\d.]+)\s*\[?V", p)
            if num:
                out.append((float(num.group(1)), float(volt.group(1)) if volt else None, p))
        return out

    torque, speed = entries(rows["stall torque"]), entries(rows["no load speed"])

    def pick(es):
        at = [e for e in es if rec_v is not None and e[1] == rec_v]
        chosen = at or es
        return chosen[0], len(chosen) > 1, chosen

    (t, _, _), (s, several, all_s) = pick(torque), pick(speed)
    detail = ""
    if several:
        detail = (f"; the page lists several no-load speeds at that voltage ({'; '.join(e[2] for e in all_s)}): "
                  f"the first, the motor's free-running speed, is used")
    elif len(torque) > 1:
        detail = "; the figure at the recommended input voltage is used"
    volts = t[1] if t[1] is not None else rec_v
    if volts is not None and rec_v is not None and volts != rec_v:
        detail += (f"; the figures are stated at {volts} V only, not at the recommended input voltage "
                   f"({rec_v} V), so nominal_voltage_v is {volts}")
    if s[1] is not None and volts is not None and s[1] != volts:
        raise ValueError(f"no-load speed stated at {s[1]} V but stall torque at {volts} V")
    # "1.5 [N.m] (at 12 [V], 1.5 [A])", "10.9 [N.m] (at 18.5V, 7A)", "6.0Nm @ 12V, 4.1A" (not "[Nm/A]")
    amps = re.search(r",\s*([\d.]+)\s*\[?A\b", t[2])
    rpm = int(s[0]) if s[0].is_integer() else s[0]
    return PageSpec(rpm, t[0], float(amps.group(1)) if amps else None, volts, detail, t[2], s[2])
