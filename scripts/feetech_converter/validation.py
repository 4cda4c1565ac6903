"""The rules every FEETECH model file must pass before it is written: what the loader will check
(unique keys and addresses, no overlap, sign bits inside their items, initial values in range,
copies naming items), and a model number no other model of the library reports."""

from __future__ import annotations

import json
from pathlib import Path

from .items import full_range


def validate(model: dict) -> None:
    """Raises ValueError naming the first rule `model` breaks."""
    items = model["items"]
    keys = [i["key"] for i in items]
    if len(set(keys)) != len(keys):
        raise ValueError(f"duplicate keys: {sorted({k for k in keys if keys.count(k) > 1})}")
    for a, b in zip(items, items[1:]):
        if a["address"] + a["size"] > b["address"]:
            raise ValueError(f"{a['key']} ({a['address']}, {a['size']}) overlaps {b['key']} ({b['address']})")
    by_key = {i["key"]: i for i in items}
    for i in items:
        bit = i.get("sign_bit")
        if bit is not None and not 1 <= bit < 8 * i["size"]:
            raise ValueError(f"{i['key']}: sign_bit {bit} outside its {i['size']} bytes")
        lo, hi = full_range(i["size"], bit)
        lo, hi = i.get("min", lo), i.get("max", hi)
        if lo > hi or lo < full_range(i["size"], bit)[0] or hi > full_range(i["size"], bit)[1]:
            raise ValueError(f"{i['key']}: range {lo}~{hi} does not fit the item")
        if "initial_from" in i:
            if i["initial_from"] not in by_key:
                raise ValueError(f"{i['key']}: initial_from names no item {i['initial_from']!r}")
            initial = by_key[i["initial_from"]]["initial"]
        else:
            initial = i["initial"]
        if not lo <= initial <= hi or ("values" in i and initial not in i["values"]):
            raise ValueError(f"{i['key']}: initial {initial} outside its range")
    for needed in ("id", "baud_rate"):
        if needed not in by_key:
            raise ValueError(f"no {needed!r} item")
    baud = by_key["baud_rate"]
    if (baud.get("min", 0), baud.get("max")) != (0, len(model["baud_rates"]) - 1):
        raise ValueError("the Baud rate item's range is not the codes of baud_rates")


def check_model_numbers(models: list[dict], catalog: Path) -> None:
    """No two models of the library (models/catalog.json and these) report one number."""
    taken = {m["model_number"]: m["name"] for m in json.loads(catalog.read_text(encoding="utf-8"))["models"]}
    for m in models:
        other = taken.setdefault(m["model_number"], m["name"])
        if other != m["name"]:
            raise ValueError(f"{m['name']} and {other} both report model number {m['model_number']}")
