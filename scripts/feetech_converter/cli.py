"""The command line: build every model of decisions.MODELS from its reference file, validate
them, then write models/feetech/ or (--check) compare it with what would be written."""

from __future__ import annotations

from pathlib import Path

from model_converter.cli import REPO_ROOT, catalog_entry, converter_arguments, dump, write_or_check

from .builder import build_model
from .decisions import MODELS
from .reference import read_reference
from .validation import check_model_numbers, validate

DEFAULT_OUT = REPO_ROOT / "models" / "feetech"


def build_all(reference: Path) -> dict[str, str]:
    """Every output file as {file name: text}."""
    models = []
    for model in MODELS:
        path = reference / "feetech" / model.reference
        if not path.is_file():
            raise SystemExit(f"convert_feetech_models: no {path}")
        try:
            built = build_model(read_reference(path), model)
            validate(built)
        except ValueError as exc:
            raise SystemExit(f"convert_feetech_models: {model.name}: {exc}")
        models.append(built)
    try:
        check_model_numbers(models, REPO_ROOT / "models" / "catalog.json")
    except ValueError as exc:
        raise SystemExit(f"convert_feetech_models: {exc}")
    files = {f"{m['name']}.json": dump(m) for m in models}
    # FEETECH's catalog, beside DYNAMIXEL's models/catalog.json (which the DYNAMIXEL converter
    # writes whole): the library loads every maker folder's catalog.json.
    catalog = [catalog_entry(m) for m in models]
    files["catalog.json"] = dump({"models": sorted(catalog, key=lambda c: c["name"])})
    return files


def main(argv=None, description: str = "") -> int:
    """Runs the converter on `argv` (sys.argv by default); returns the exit status."""
    args = converter_arguments(description, DEFAULT_OUT).parse_args(argv)
    return write_or_check(build_all(args.reference), args.out, args.check, "feetech models",
                          "scripts/convert_feetech_models.py")
