"""Checks on every produced model: the structural rules of docs/model-format.md (validate), and
the model against the page's printed rows (cross_check)."""

from __future__ import annotations

import re
from pathlib import Path

from .decisions.catalogue import PAGE_RULES
from .markdown import parse_int, snake_key
from .page import Page
from .ranges import RangeSpec, bound_keys, full_width, parse_range

FAMILIES = {family for _, family, _ in PAGE_RULES}
TOP_REQUIRED = {"name": str, "title": str, "model_number": int, "firmware_version": int, "family": str,
                "protocols": list, "default_id": int, "baud_rates": list, "default_baud_index": int,
                "return_delay_unit_us": int, "timing": dict, "motion": dict, "source": str, "items": list}
MOTION_KEYS = {"degrees_per_pulse", "velocity_unit_rpm", "current_unit_ma", "no_load_speed_rpm", "stall_torque_nm",
               "stall_current_a", "nominal_voltage_v", "acceleration_unit_rpm2", "current_zero"}
ITEM_KEYS = {"key", "name", "address", "size", "access", "area", "initial", "initial_from", "signed", "min",
             "max", "values", "limit_min", "limit_max", "unit", "absent_in", "note"}
# The protocols a DYNAMIXEL model file may list (FEETECH files come from the other converter).
PROTOCOLS = {1, 2, "modbus"}


def validate(model: dict) -> None:
    """Raise AssertionError naming the model and the rule broken."""
    name = model.get("name", "?")

    def need(cond, msg):
        if not cond:
            raise AssertionError(f"{name}: {msg}")

    for k, t in TOP_REQUIRED.items():
        need(isinstance(model.get(k), t) and not isinstance(model.get(k), bool), f"{k} missing or not {t.__name__}")
    need(model["family"] in FAMILIES, "unknown family")
    need(0 <= model["model_number"] <= 65535, "model_number out of 0 ~ 65535")
    need(0 <= model["firmware_version"] <= 255, "firmware_version out of 0 ~ 255")
    need(model["protocols"] and set(model["protocols"]) <= PROTOCOLS, "protocols")
    need(len(set(model["protocols"])) == len(model["protocols"]), "protocols: one listed twice")
    seen = {model["firmware_version"]}
    for v in model.get("firmware_variants", []):
        need(set(v) <= {"firmware_version", "indirect", "notes"}, f"firmware_variants: unknown fields {set(v)}")
        need(isinstance(v.get("firmware_version"), int) and 0 <= v["firmware_version"] <= 255,
             "firmware_variants: firmware_version out of 0 ~ 255")
        need(v["firmware_version"] not in seen, f"firmware_variants: firmware {v['firmware_version']} twice")
        seen.add(v["firmware_version"])
        need("indirect" in model and isinstance(v.get("indirect"), list) and v["indirect"],
             "firmware_variants: indirect must replace the model's indirect blocks")
    idx = [b["index"] for b in model["baud_rates"]]
    need(len(idx) == len(set(idx)), "duplicate baud index")
    need(model["default_baud_index"] in idx, "default baud index not in baud_rates")
    for k in ("ping_us", "read_us", "write_us", "write_per_byte_us", "boot_ms"):
        need(isinstance(model["timing"].get(k), int), f"timing.{k}")
    for k in ("degrees_per_pulse", "velocity_unit_rpm"):
        need(isinstance(model["motion"].get(k), (int, float)), f"motion.{k}")
    need(set(model["motion"]) <= MOTION_KEYS, f"motion: unknown fields {set(model['motion']) - MOTION_KEYS}")
    for k, v in model["motion"].items():
        need(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0, f"motion.{k} not a positive number")
    items = model["items"]
    keys, addrs, occupied = set(), set(), {}
    by_key = {i["key"]: i for i in items}
    for it in items:
        k = it["key"]
        need(set(it) <= ITEM_KEYS, f"{k}: unknown fields {set(it) - ITEM_KEYS}")
        need(re.fullmatch(r"[a-z0-9_]+", k) is not None, f"{k}: key not snake_case")
        need(k not in keys, f"duplicate key {k}")
        need(it["address"] not in addrs, f"duplicate address {it['address']}")
        keys.add(k)
        addrs.add(it["address"])
        need(it["size"] in (1, 2, 4), f"{k}: size {it['size']}")
        need(it["access"] in ("R", "RW") and it["area"] in ("EEPROM", "RAM", "Hybrid"), f"{k}: access/area")
        for a in range(it["address"], it["address"] + it["size"]):
            need(a not in occupied, f"{k} overlaps {occupied.get(a)}")
            occupied[a] = k
        need(("initial" in it) != ("initial_from" in it), f"{k}: exactly one of initial / initial_from")
        if "absent_in" in it:
            absent = it["absent_in"]
            need(isinstance(absent, list) and absent and len(set(absent)) == len(absent) and
                 set(absent) <= set(model["protocols"]) and set(absent) != set(model["protocols"]),
                 f"{k}: absent_in must list, once each, some but not all of the model's protocols")
        lo, hi = full_width(it["size"], it.get("signed", False))
        lo, hi = it.get("min", lo), it.get("max", hi)
        need(("min" in it) == ("max" in it), f"{k}: min without max")
        need(lo <= hi, f"{k}: min > max")
        need(full_width(it["size"], it.get("signed", False))[0] <= lo and
             hi <= full_width(it["size"], it.get("signed", False))[1], f"{k}: range exceeds the item width")
        if "initial" in it:
            need(isinstance(it["initial"], int), f"{k}: initial not an integer")
            need(lo <= it["initial"] <= hi, f"{k}: initial {it['initial']} outside {lo} ~ {hi}")
            if "values" in it:
                need(it["initial"] in it["values"], f"{k}: initial not in values")
        else:
            need(it["initial_from"] in by_key, f"{k}: initial_from names no item")
        for side in ("limit_min", "limit_max"):
            if side in it:
                need(it[side].lstrip("-") in by_key, f"{k}: {side} names no item")
    for it in items:
        if "initial_from" in it:
            src = by_key[it["initial_from"]]
            lo, hi = it.get("min", full_width(it["size"], False)[0]), it.get("max", full_width(it["size"], False)[1])
            need("initial" in src and lo <= src["initial"] <= hi, f"{it['key']}: initial_from value outside range")
    for blk in model.get("indirect", []):
        for i in range(blk["count"]):
            a = next((x for x in items if x["address"] == blk["address"] + 2 * i), None)
            d = next((x for x in items if x["address"] == blk["data"] + i), None)
            need(a is not None and a["size"] == 2 and a["key"].startswith("indirect_address_"),
                 f"indirect block {blk}: address entry {i}")
            need(d is not None and d["size"] == 1 and d["key"].startswith("indirect_data_"),
                 f"indirect block {blk}: data entry {i}")
    if "axes" in model:
        need(model["axes"] == 2 and all(k in by_key for k in model.get("shared_items", [])), "axes/shared_items")


def cross_check(page: Page, model: dict) -> list[str]:
    """Every printed row appears as an item with the same identity; nothing extra.

    Returns the list of documented deviations (each carries a note in the item); raises on
    anything undocumented.
    """
    items = {i["address"]: i for i in model["items"]}
    problems, deviations = [], []
    if len(items) != len(page.rows):
        problems.append(f"{len(items)} items for {len(page.rows)} rows")
    for row in page.rows:
        it = items.get(row.address)
        if it is None:
            problems.append(f"row {row.name}({row.address}) has no item")
            continue
        if (it["name"], it["size"], it["area"]) != (row.name, row.size, row.area):
            problems.append(f"{row.name}: name/size/area differ")
        if it["access"] != row.access:
            if row.access == "R/RW" and "note" in it:
                deviations.append(f"{it['key']}: access R/RW -> RW")
            else:
                problems.append(f"{row.name}: access {it['access']} != {row.access}")
        n = parse_int(row.initial)
        if n is not None and it.get("initial") != n:
            if "initial:" in it.get("note", ""):
                deviations.append(f"{it['key']}: initial {n} -> {it.get('initial')}")
            else:
                problems.append(f"{row.name}: initial {it.get('initial')} != printed {n}")
        spec = None
        if row.minmax is not None:
            lo, hi = (parse_int(x) for x in row.minmax)
            if lo is not None:
                spec = RangeSpec(min=lo, max=hi)
        elif "range" in page.columns:
            spec = parse_range(row.range)
        if spec is None:
            continue
        if spec.values is not None and len(spec.values) > 1:
            if it.get("values") != spec.values:
                problems.append(f"{row.name}: values {it.get('values')} != printed {spec.values}")
            continue
        if spec.min is not None and it.get("min") != spec.min:
            if "note" in it and "range" in it["note"]:
                deviations.append(f"{it['key']}: min {spec.min} -> {it.get('min')}")
            else:
                problems.append(f"{row.name}: min {it.get('min')} != printed {spec.min}")
        if spec.max is not None and it.get("max") != spec.max:
            if "note" in it and "range" in it["note"]:
                deviations.append(f"{it['key']}: max {spec.max} -> {it.get('max')}")
            else:
                problems.append(f"{row.name}: max {it.get('max')} != printed {spec.max}")
        for side, ref in (("limit_min", spec.lo_ref), ("limit_max", spec.hi_ref)):
            if ref and it.get(side, "").lstrip("-") not in bound_keys(ref[1]):
                problems.append(f"{row.name}: {side} {it.get(side)} != printed {ref}")
    if problems:
        raise AssertionError(f"{page.name}: cross-check failed:\n  " + "\n  ".join(problems))
    return deviations


def differences(files: dict[str, str], out: Path) -> tuple[list[str], list[str]]:
    """--check: the files of `files` that are missing or differ in `out`, and the model files in
    `out` that nothing generates (stale)."""
    differ = [f for f, text in sorted(files.items())
              if not (out / f).exists() or (out / f).read_text(encoding="utf-8") != text]
    stale = sorted(p.name for p in out.glob("*.json") if p.name not in files)
    return differ, stale
