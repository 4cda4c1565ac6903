"""Which SDK file each model view is compared with.

A model and an SDK file pair up:
- by model number: the file `dynamixel.model` registers under the model's number (of several
  models with that number, the one whose name is the file's, e.g. xc430-w150 for
  xc430_w150.model when an XC430-T150BB also prints 1070);
- by file name, for a file no model pairs with by number (xw430_t200.model, which
  `dynamixel.model` does not list): the model whose name is the file's ('xw430-t200'); when
  the file is registered under another number, the comparison reports the model number;
- by shared number: a model whose number is registered for a file that pairs with another
  model is also compared with that file, since EasySDK loads it for the number it pings
  (XW430-T200 at 1270 gets xw430_t333.model).
A name alone never pairs a file that pairs by number: rh_p12_rn.model is 35074, the
RH-P12-RN(A), so the RH-P12-RN (35073) has no SDK file.

Firmware: `x_fwNN.model` is x's table for firmware NN and older, `x.model` for newer firmware
(xl330_m288_fw52.model: before V53). The model file's own table (its default firmware) is
compared with `x.model`; each of its `firmware_variants` with the file its firmware selects;
a `_fwNN` file no variant selects is not compared ('no variant'). A client that picks its table
by the Firmware Version it reads (ROS 2's dynamixel_hardware_interface) loads `x_fwNN.model`
for a default firmware of NN or older, so that mismatch is reported: as a difference once the
model has variants (its firmware versions then claim a layout), for information before."""
import re
from dataclasses import dataclass, field

from model_views import Model, ModelView
from sdk_tables import SdkFile


@dataclass(frozen=True)
class Comparison:
    """One model view against one SDK file."""

    sdk: SdkFile
    view: ModelView
    how: str  # why they pair, for the summary
    expected_number: int | None  # dynamixel.model's number for the file, None if unregistered
    firmware_selects: str | None = None  # the file the view's firmware selects, when not `sdk`


@dataclass
class Pairing:
    comparisons: list = field(default_factory=list)
    not_compared: list = field(default_factory=list)  # (sdk file, reason)
    sdk_without_model: list = field(default_factory=list)  # (sdk file, number or None)
    models_without_sdk: list = field(default_factory=list)  # (model name, number, reason)
    errors: list = field(default_factory=list)  # pairings that cannot be decided
    pairs: dict = field(default_factory=dict)  # SDK model file -> the model it pairs with
    shared: list = field(default_factory=list)  # (SDK model file, model) by a shared number
    firmware_info: list = field(default_factory=list)  # default firmware selecting another table


def folded_name(name: str) -> str:
    """'xw430-t200', 'xw430_t200.model' -> 'xw430t200'."""
    return re.sub(r"[^0-9a-z]", "", name.casefold().removesuffix(".model"))


def select_file(view: ModelView, family: list[SdkFile]) -> SdkFile:
    """The file of `family` (a model's file and its `_fwNN` files) for the view's firmware."""
    limited = sorted((f for f in family if f.last_firmware is not None), key=lambda f: f.last_firmware)
    for f in limited:
        if view.firmware_version <= f.last_firmware:
            return f
    return next(f for f in family if f.last_firmware is None)


def _newer_than(family: list[SdkFile]) -> int | None:
    limits = [f.last_firmware for f in family if f.last_firmware is not None]
    return max(limits) if limits else None


def _families(sdk_files: dict[str, SdkFile], out: Pairing) -> dict[str, list[SdkFile]]:
    """Model file -> it and its `_fwNN` files; a `_fwNN` file without its model file is an error."""
    families: dict[str, list[SdkFile]] = {}
    for f in sorted(sdk_files.values(), key=lambda f: f.file):
        families.setdefault(f.base_file, []).append(f)
    for base in [b for b in families if b not in sdk_files]:
        out.errors.append(f"{families.pop(base)[0].file}: no {base} beside it")
    return families


def _pair_files(registry, families, models, out: Pairing) -> dict[str, tuple[Model, str]]:
    """SDK model file -> (its model, why), by number first, then by name."""
    by_number: dict[int, list[Model]] = {}
    for m in models:
        by_number.setdefault(m.model_number, []).append(m)
    by_name = {folded_name(m.name): m for m in models}
    folded_files = {folded_name(b) for b in families}
    paired = {}
    for base in families:
        number = registry.get(base)
        candidates = by_number.get(number, []) if number is not None else []
        # A model named like another SDK file has that file and only shares this number.
        own = [m for m in candidates if folded_name(m.name) == folded_name(base)]
        free = own or [m for m in candidates if folded_name(m.name) not in folded_files]
        if len(free) == 1:
            paired[base] = (free[0], f"model number {number}")
        elif free:
            out.errors.append(f"{base}: models {', '.join(m.name for m in free)} all have {number} "
                              f"and none has the file's name")
        elif folded_name(base) in by_name:
            registered = "not in dynamixel.model" if number is None else f"dynamixel.model: {number}"
            paired[base] = (by_name[folded_name(base)], f"file name ({registered})")
        else:
            out.sdk_without_model.append((base, number))
    return paired


def _shared(registry, families, paired, models) -> list[tuple[str, Model, str]]:
    """(file, model, why) for each model whose number is registered for a file it does not pair
    with: EasySDK loads that file for it."""
    registered_file = {n: f for f, n in registry.items()}
    out = []
    for m in models:
        f = registered_file.get(m.model_number)
        if f in families and (f not in paired or paired[f][0] is not m):
            out.append((f, m, f"shares model number {m.model_number} with {f}: EasySDK loads it for {m.name}"))
    return out


def _compare_views(base, model: Model, how: str, family, number, out: Pairing):
    """A comparison per view of `model` with its file of `family` (module docstring)."""
    model_file = next(f for f in family if f.last_firmware is None)
    selected = set()
    for view in model.views:
        by_firmware = select_file(view, family)
        chosen = by_firmware if view.variant else model_file
        selected.add(chosen.file)
        why = how + (f"; firmware {view.firmware_version} selects {by_firmware.file}" if len(family) > 1 else "")
        mismatch = by_firmware.file if by_firmware is not chosen else None
        if mismatch and len(model.views) == 1:
            out.firmware_info.append(f"{view.label} is compared with {chosen.file}, but a client that picks its "
                                     f"table by Firmware Version loads {mismatch} for firmware "
                                     f"{view.firmware_version}")
            mismatch = None
        out.comparisons.append(Comparison(chosen, view, why, number, mismatch))
    for f in family:
        if f.file in selected:
            continue
        if f.last_firmware is not None:
            reason = f"no variant ({model.name} has no firmware variant {f.last_firmware} or older)"
        else:
            reason = f"no variant ({model.name} has no firmware newer than {_newer_than(family)})"
        out.not_compared.append((f.file, reason))


def pair(registry: dict[str, int], sdk_files: dict[str, SdkFile], models: list[Model]) -> Pairing:
    """Every comparison of `models` with `sdk_files` (file name -> parsed file)."""
    out = Pairing()
    families = _families(sdk_files, out)
    paired = _pair_files(registry, families, models, out)
    shared = _shared(registry, families, paired, models)
    out.pairs = {b: m.name for b, (m, _) in paired.items()}
    out.shared = [(b, m.name) for b, m, _ in shared]
    for base, model, how in [(b, m, h) for b, (m, h) in paired.items()] + shared:
        _compare_views(base, model, how, families[base], registry.get(base), out)
    compared = {c.view.name for c in out.comparisons}
    for m in models:
        if m.name in compared:
            continue
        owner = next((b for b in families if folded_name(b) == folded_name(m.name)), None)
        if owner in paired:
            reason = f"{owner} is {registry.get(owner)}, paired with {paired[owner][0].name}"
        else:
            reason = "DynamixelSDK ships no table for it"
        out.models_without_sdk.append((m.name, m.model_number, reason))
    return out
