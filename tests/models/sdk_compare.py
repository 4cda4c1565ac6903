"""One model view against one SDK file: the model number, and the address and size of every
item the SDK file names. Then the model's `sdk-control-tables:` notes explain differences
(sdk_notes.py); what no note explains fails, and so does a note that explains nothing."""
from dataclasses import dataclass, field
from pathlib import Path

import sdk_names
from sdk_notes import Explanation, explanations
from sdk_pairing import Comparison

MODEL_NUMBER = "Model Number"
FIRMWARE_VERSION = "Firmware Version"


@dataclass
class Difference:
    sdk_file: str
    view: str  # the view's label
    model: str
    item: str  # the SDK's Data Name (FIRMWARE_VERSION: the firmware's table), or MODEL_NUMBER
    text: str
    explainable: bool = True  # False: the test's own mapping failed (an ambiguous name)
    explained_by: Explanation | None = None

    def line(self) -> str:
        return f"{self.sdk_file} vs {self.view}: {self.item}: {self.text}"


@dataclass
class Result:
    compared_items: int = 0
    differences: list = field(default_factory=list)
    note_errors: list = field(default_factory=list)  # malformed or stale explanations

    @property
    def explained(self) -> list:
        return [d for d in self.differences if d.explained_by is not None]

    @property
    def unexplained(self) -> list:
        return [d for d in self.differences if d.explained_by is None]


def _describe(items) -> str:
    return ", ".join(f"{i.name!r} ({i.address}, {i.size})" for i in items) or "nothing"


def compare(c: Comparison) -> tuple[int, list[Difference]]:
    """(items compared, differences) of one comparison."""
    view, diffs = c.view, []

    def differ(item: str, text: str, explainable: bool = True):
        diffs.append(Difference(c.sdk.file, view.label, view.name, item, text, explainable))

    if c.expected_number is not None and view.model_number != c.expected_number:
        differ(MODEL_NUMBER, f"the model reports {view.model_number}, dynamixel.model registers "
                             f"{c.sdk.base_file} as {c.expected_number}")
    if c.firmware_selects is not None:
        differ(FIRMWARE_VERSION, f"firmware {view.firmware_version} selects {c.firmware_selects} for a client "
                                 f"that picks its table by Firmware Version (ROS 2 dynamixel_hardware_interface), "
                                 f"but the model's table is compared with {c.sdk.file}")
    slots: dict[str, tuple[int, int]] = {}  # indirect alias -> (slot n, SDK address)
    for row in c.sdk.items:
        found = sdk_names.find(row.name, row.address, view)
        if not found.items:
            at = _describe(i for i in view.items if i.address == row.address)
            kind = sdk_names.INDIRECT_ALIASES.get(row.name)
            wanted = f"an Indirect {kind} n" if kind else "this name or an alias of it"
            differ(row.name, f"SDK {row.address}, size {row.size}: no item of the model is {wanted} "
                             f"(at {row.address} the model has {at})")
            continue
        if found.item is None:
            differ(row.name, f"stands for several items of the model ({_describe(found.items)}, "
                             f"rule '{found.rule}'): the test's name mapping is wrong", explainable=False)
            continue
        item = found.item
        called = "" if item.name == row.name else f" (the model's {item.name!r})"
        if item.address != row.address:
            differ(row.name, f"SDK address {row.address}, model {item.address}{called}")
        if item.size != row.size:
            differ(row.name, f"SDK size {row.size}, model {item.size}{called}")
        slot = sdk_names.indirect_slot(item)
        if row.name in sdk_names.INDIRECT_ALIASES and slot is not None:
            slots[row.name] = (slot[1], row.address)
    for use in ("Write", "Read"):
        a, d = slots.get(f"Indirect Address {use}"), slots.get(f"Indirect Data {use}")
        if a and d and a[0] != d[0]:
            differ(f"Indirect Data {use}",
                   f"Indirect Address {use} ({a[1]}) is the model's Indirect Address {a[0]}, but Indirect "
                   f"Data {use} ({d[1]}) is its Indirect Data {d[0]}: the SDK reads one slot's data "
                   f"through another's address")
    return len(c.sdk.items), diffs


def check(comparisons: list[Comparison], pages_dir: Path | None, models=()) -> Result:
    """Every comparison, with each model's notes applied: the explained differences, the
    unexplained ones, and the notes that are malformed or explain nothing (also those of the
    `models` no comparison reaches)."""
    result = Result()
    by_notes: dict[tuple, list] = {}  # (model, notes) -> differences of its views with those notes
    for c in comparisons:
        count, diffs = compare(c)
        result.compared_items += count
        result.differences.extend(diffs)
        by_notes.setdefault((c.view.name, c.view.notes), []).extend(diffs)
    for m in models:
        for view in m.views:
            by_notes.setdefault((view.name, view.notes), [])
    used: dict[str, set] = {}  # model -> notes that explained something
    offered: dict[str, dict] = {}  # model -> note -> Explanation
    for (model, notes), diffs in by_notes.items():
        found, errors = explanations(notes, pages_dir)
        for e in errors:
            if f"{model}: {e}" not in result.note_errors:  # the file's notes are in every view's
                result.note_errors.append(f"{model}: {e}")
        for e in found:
            offered.setdefault(model, {})[e.note] = e
        for d in diffs:
            if not d.explainable:
                continue
            match = next((e for e in found if (e.file, e.item) == (d.sdk_file, d.item)), None)
            if match is not None:
                d.explained_by = match
                used.setdefault(model, set()).add(match.note)
    for model, notes in offered.items():
        for note, e in notes.items():
            if note not in used.get(model, set()):
                result.note_errors.append(f"{model}: explains no difference (is {e.file} compared with "
                                          f"this model, and does {e.item!r} still differ?): {note!r}")
    return result
