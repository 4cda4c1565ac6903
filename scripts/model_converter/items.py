"""An item on its way to JSON (Item) and a page on its way to a model (Draft): the state that the
builder's passes read and fill in."""

from __future__ import annotations

from dataclasses import dataclass, field

from .decisions.catalogue import lineage, variant_of
from .page import Page, Row
from .ranges import full_width
from .reference import Reference


@dataclass
class Item:
    """One item of the model, with the notes of every choice made for it."""
    row: Row
    key: str
    initial: int | None = None
    initial_from: str | None = None
    signed: bool = False
    min: int | None = None
    max: int | None = None
    values: list | None = None
    limit_min: str | None = None
    limit_max: str | None = None
    unit: str | None = None
    notes: list = field(default_factory=list)
    range_from: str = ""       # "table", "choice", ... (for the summary)
    absent_in: list = field(default_factory=list)   # protocols whose map leaves the item out (modbus_map.py)

    def to_json(self) -> dict:
        """The item as docs/model-format.md writes it (fields in that order, defaults omitted)."""
        d = {"key": self.key, "name": self.row.name, "address": self.row.address, "size": self.row.size,
             "access": self.access, "area": self.row.area}
        if self.initial_from is not None:
            d["initial_from"] = self.initial_from
        else:
            d["initial"] = self.initial
        if self.signed:
            d["signed"] = True
        if self.min is not None:
            d["min"] = self.min
        if self.max is not None:
            d["max"] = self.max
        if self.values is not None:
            d["values"] = self.values
        if self.limit_min is not None:
            d["limit_min"] = self.limit_min
        if self.limit_max is not None:
            d["limit_max"] = self.limit_max
        if self.unit:
            d["unit"] = self.unit
        if self.absent_in:
            d["absent_in"] = self.absent_in
        if self.notes:
            d["note"] = "; ".join(self.notes)
        return d

    @property
    def access(self) -> str:
        """"R" or "RW" ("R/RW" is stored as RW)."""
        return "RW" if self.row.access == "R/RW" else self.row.access

    def static_range(self) -> tuple[int, int]:
        """min ~ max, or the full width of the item where it has no range."""
        if self.min is not None:
            return self.min, self.max
        return full_width(self.row.size, self.signed)


class Draft:
    """One page being turned into a model: its items so far and the model-level notes, in the
    order they are written."""

    def __init__(self, ref: Reference, page: Page, donors: dict[str, Page]):
        self.ref, self.page, self.donors = ref, page, donors
        self.name, self.family = page.name, page.family
        self.tsv = ref.tsv[page.name]
        self.notes: list[str] = []
        self.items: list[Item] = []
        self.by_key: dict[str, Item] = {}
        self.by_addr: dict[int, Item] = {}

    @property
    def variant(self) -> str:
        """The family, or the product line within it where that decides something (X330)."""
        return variant_of(self.family, self.page.group)

    @property
    def lineage(self) -> tuple[str, ...]:
        """The page, its variant, family and parent families: the keys decisions are looked up by,
        most specific first (a decision for one page is an entry under its name)."""
        return (self.name, *lineage(self.family, self.page.group))

    def lookup(self, table: dict, default=KeyError):
        """The entry of a per-variant decision table for the first key of the lineage it has;
        `default` where it has none (KeyError raises)."""
        for key in self.lineage:
            if key in table:
                return table[key]
        if default is KeyError:
            raise KeyError(f"{self.name}: no decision for any of {', '.join(self.lineage)}")
        return default

    def is_in(self, families) -> bool:
        """True when a set (or table) of families names the variant, the family or a parent."""
        return any(key in families for key in self.lineage)

    def add(self, item: Item) -> None:
        """Appends `item` and indexes it by key and address."""
        self.items.append(item)
        self.by_key[item.key] = item
        self.by_addr[item.row.address] = item
