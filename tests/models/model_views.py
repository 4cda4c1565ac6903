"""dxlemu's model files (models/catalog.json and the files it names) as the SDK cross-check sees
them: per model, one view per firmware the file describes. The file itself is the default
firmware; each entry of its optional `firmware_variants` list (`firmware_version`, and the
`indirect` blocks that differ) is another view, whose Indirect Address/Data items are the ones
its blocks define (Indirect Address n at `address + 2*i`, Indirect Data n at `data + i`, n
counted from 1 across the blocks in order), replacing the file's."""
import json
import re
from dataclasses import dataclass
from pathlib import Path

INDIRECT_NAME = re.compile(r"^Indirect (Address|Data) (\d+)$")


@dataclass(frozen=True)
class ModelItem:
    """One item of a model view: key, name, address and size."""

    key: str
    name: str
    address: int
    size: int


@dataclass(frozen=True)
class ModelView:
    """A model at one firmware: what the cross-check compares with an SDK file."""

    name: str  # the model's name (models/catalog.json)
    model_number: int
    firmware_version: int
    variant: bool  # False: the file's default firmware; True: one of its firmware_variants
    items: tuple
    notes: tuple  # the file's notes, then the variant's

    @property
    def label(self) -> str:
        kind = "variant" if self.variant else "default"
        return f"{self.name} (firmware {self.firmware_version}, {kind})"


@dataclass(frozen=True)
class Model:
    """A model file: its default view and its firmware variants' views."""

    name: str
    file: str
    model_number: int
    views: tuple

    @property
    def default(self) -> ModelView:
        return self.views[0]


def _items(raw: list, origin: str) -> list[ModelItem]:
    out = []
    for i, it in enumerate(raw):
        try:
            out.append(ModelItem(str(it["key"]), str(it["name"]), int(it["address"]), int(it["size"])))
        except (KeyError, TypeError, ValueError) as e:
            raise ValueError(f"{origin}: /items/{i}: needs key, name, address and size ({e})") from e
    return out


def indirect_items(blocks: list, origin: str) -> list[ModelItem]:
    """The Indirect Address/Data items that `blocks` ([{address, data, count}]) define."""
    out, n = [], 0
    for b, block in enumerate(blocks):
        try:
            address, data, count = int(block["address"]), int(block["data"]), int(block["count"])
        except (KeyError, TypeError, ValueError) as e:
            raise ValueError(f"{origin}: indirect block {b}: needs address, data and count ({e})") from e
        for i in range(count):
            n += 1
            out.append(ModelItem(f"indirect_address_{n}", f"Indirect Address {n}", address + 2 * i, 2))
            out.append(ModelItem(f"indirect_data_{n}", f"Indirect Data {n}", data + i, 1))
    return out


def _is_indirect(item: ModelItem) -> bool:
    return INDIRECT_NAME.match(item.name) is not None or item.key.startswith(("indirect_address_", "indirect_data_"))


def _notes(raw, origin: str) -> list[str]:
    if raw is None:
        return []
    if not isinstance(raw, list) or not all(isinstance(n, str) for n in raw):
        raise ValueError(f"{origin}: notes must be a list of strings")
    return list(raw)


def model_from_json(doc: dict, origin: str) -> Model:
    """The views of one parsed model file."""
    try:
        name, number, firmware = str(doc["name"]), int(doc["model_number"]), int(doc["firmware_version"])
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"{origin}: needs name, model_number and firmware_version ({e})") from e
    items = _items(doc.get("items", []), origin)
    notes = _notes(doc.get("notes"), origin)
    views = [ModelView(name, number, firmware, False, tuple(items), tuple(notes))]
    variants = doc.get("firmware_variants", [])
    if not isinstance(variants, list):
        raise ValueError(f"{origin}: firmware_variants must be a list")
    for v, variant in enumerate(variants):
        where = f"{origin}: /firmware_variants/{v}"
        try:
            version = int(variant["firmware_version"])
        except (KeyError, TypeError, ValueError) as e:
            raise ValueError(f"{where}: needs firmware_version ({e})") from e
        own = items
        if "indirect" in variant:
            own = [i for i in items if not _is_indirect(i)] + indirect_items(variant["indirect"], where)
        views.append(ModelView(name, number, version, True, tuple(own),
                               tuple(notes + _notes(variant.get("notes"), where))))
    return Model(name, origin, number, tuple(views))


def load_models(models_dir: Path) -> list[Model]:
    """Every model models_dir/catalog.json names, in catalog order. The catalog's name and model
    number must be the file's: the pairing reads the catalog's."""
    catalog_path = models_dir / "catalog.json"
    try:
        catalog = json.loads(catalog_path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise ValueError(f"cannot read {catalog_path}: {e}") from e
    out = []
    for entry in catalog.get("models", []):
        path = models_dir / entry["file"]
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as e:
            raise ValueError(f"cannot read {path}: {e}") from e
        model = model_from_json(doc, entry["file"])
        if (model.name, model.model_number) != (entry["name"], entry["model_number"]):
            raise ValueError(f"catalog.json says {entry['name']} {entry['model_number']}, "
                             f"{entry['file']} says {model.name} {model.model_number}")
        out.append(model)
    if not out:
        raise ValueError(f"{catalog_path}: no models")
    return out
