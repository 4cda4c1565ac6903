"""Ranges: what a Range cell says (RangeSpec, parse_range), the full width of an item, and the
shape of a documented range choice with the evidence it must be found in (RangeChoice; the
choices themselves are data in decisions/range_choices.py).

How an item's range is decided, in order, is item_ranges.py.
"""

from __future__ import annotations

import functools
import operator
import re
from dataclasses import dataclass, field

from .markdown import ELLIPSES, clean_cell, norm_space, parse_int, snake_key

RANGE_RE = re.compile(r"(-?[\d,]+)\s*~\s*(-?[\d,]+)")
# "- Current Limit(66)"; also "Voltage(PWM) Limit(64)", a name with its other name in brackets
LIMIT_RE = re.compile(r"^(-?)\s*([A-Za-z][A-Za-z ]*?(?:\([A-Za-z]+\)\s*[A-Za-z ]*?)?)\s*\((\d+)\)$")


@dataclass
class RangeSpec:
    """What a Range cell says."""
    min: int | None = None
    max: int | None = None
    values: list | None = None
    lo_ref: tuple | None = None   # (negated, name, address)
    hi_ref: tuple | None = None
    extra: list = field(default_factory=list)   # further ranges printed in the same cell
    raw: str = ""


def parse_range(cell: str) -> RangeSpec | None:
    """Range cell -> RangeSpec; None for '-' / empty."""
    t = clean_cell(cell)
    if t in ("", "-") or t in ELLIPSES:
        return None
    spec = RangeSpec(raw=t)
    if "~" in t:
        lo, hi = [s.strip() for s in t.split("~", 1)]
        # "0 ~ 32,767 0 ~ 32,737": two ranges in one cell (velocity- vs time-based profile)
        ranges = RANGE_RE.findall(t)
        if len(ranges) > 1 and parse_int(ranges[0][0]) is not None:
            spec.min, spec.max = parse_int(ranges[0][0]), parse_int(ranges[0][1])
            spec.extra = [(parse_int(a), parse_int(b)) for a, b in ranges[1:]]
            return spec
        # "0 ~ 252 (DYNAMIXEL Protocol 2.0) 1 ~ 247 (Modbus)"
        if ranges and "(" in t and parse_int(lo) is not None:
            spec.min, spec.max = parse_int(ranges[0][0]), parse_int(ranges[0][1])
            spec.extra = [(parse_int(a), parse_int(b)) for a, b in ranges[1:]]
            return spec
        for side, text in (("lo", lo), ("hi", hi)):
            n = parse_int(text)
            if n is not None:
                setattr(spec, "min" if side == "lo" else "max", n)
                continue
            m = LIMIT_RE.match(text)
            if not m:
                raise ValueError(f"range cell not understood: {t!r}")
            setattr(spec, f"{side}_ref", (m.group(1) == "-", m.group(2).strip(), int(m.group(3))))
        return spec
    if "," in t and all(parse_int(x) is not None for x in t.split(",")):
        spec.values = [parse_int(x) for x in t.split(",")]
        return spec
    n = parse_int(t)
    if n is not None:
        spec.values = [n]     # a lone number (Startup Configuration's "3"): resolved by the caller
        return spec
    # "0x20(Overload) 0x10(Electrical Shock) ...": the bits of a mask, any combination of them
    bits = re.findall(r"0x([0-9A-Fa-f]+)\s*\([^)]*\)", t)
    if bits and not re.sub(r"0x[0-9A-Fa-f]+\s*\([^)]*\)", "", t).strip():
        spec.min, spec.max = 0, functools.reduce(operator.or_, (int(b, 16) for b in bits))
        return spec
    raise ValueError(f"range cell not understood: {t!r}")


def bound_keys(name: str) -> set[str]:
    """The keys a bound's name in a Range cell may stand for: its snake key, and for a name with
    its other name in brackets ('Voltage(PWM) Limit', DYNAMIXEL-Y for PWM Limit(64)) that one's."""
    return {snake_key(name), snake_key(re.sub(r"^\w+\s*\((\w+)\)\s*", r"\1 ", name))}


def full_width(size: int, signed: bool) -> tuple[int, int]:
    """(min, max) of a `size`-byte item, two's complement when `signed`."""
    bits = 8 * size
    return (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)


@dataclass(frozen=True)
class RangeChoice:
    """The range of items a page leaves open, for some families, and where that is stated."""
    families: frozenset
    keys: tuple
    min: int | None
    max: int | None
    evidence: str            # reference-relative file, "PAGE" (the model's own page) or a URL
    quotes: tuple = ()       # at least one must occur in the evidence file (whitespace-normalised)
    note: str = ""           # added to the item's note; with min None, the note is all there is
    signed: bool = False     # the range needs the item to be signed


def rc(families, keys, lo, hi, evidence, quotes=(), note="", signed=False) -> RangeChoice:
    """A RangeChoice written compactly: families "ax rx", one key or several, one quote or several."""
    if isinstance(keys, str):
        keys = (keys,)
    if isinstance(quotes, str):
        quotes = (quotes,)
    return RangeChoice(frozenset(families.split()), tuple(keys), lo, hi, evidence, tuple(quotes),
                       note, signed)


def find_choice(choices: list[RangeChoice], lineage: tuple[str, ...], key: str) -> RangeChoice | None:
    """The first choice for `key` in the first family of `lineage` (variant, family, parents)
    that has one, if any."""
    for family in lineage:
        found = next((c for c in choices if family in c.families and key in c.keys), None)
        if found is not None:
            return found
    return None


def evidence_found(choice: RangeChoice, page_text: str, read) -> bool:
    """True when the choice's evidence holds one of its quotes (whitespace-normalised); a URL is
    taken on trust. `read(rel)` returns a reference file's text; "PAGE" is `page_text`."""
    if choice.evidence.startswith("http"):
        return True
    text = page_text if choice.evidence == "PAGE" else read(choice.evidence)
    flat = norm_space(text)
    return not choice.quotes or any(norm_space(q) in flat for q in choice.quotes)
