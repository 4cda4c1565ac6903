"""The command line: build every model of CONVERTED_PAGES, validate and cross-check each, then
write the files or (--check) compare them with what is on disk."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from .builder import build_model
from .decisions.catalogue import CONVERTED_PAGES, classify, lineage
from .decisions.item_rules import BORROWED_ROWS, RANGE_DONORS
from .page import borrow_rows, read_page
from .reference import Reference
from .validation import cross_check, differences, validate

REPO_ROOT = Path(__file__).resolve().parent.parent.parent
DEFAULT_REFERENCE = REPO_ROOT.parent / "shared" / "reference"
DEFAULT_OUT = REPO_ROOT / "models"


def dump(obj) -> str:
    """JSON as the model files are written: two-space indent, UTF-8, final newline."""
    return json.dumps(obj, indent=2, ensure_ascii=False) + "\n"


def catalog_entry(model: dict) -> dict:
    """A model's entry in its catalog.json: what the emulator's library knows of it before it reads
    the file (docs/model-format.md "The catalog"), so every member the library finds, lists,
    filters or refuses duplicates by. The file must say the same; the library checks it."""
    entry = {"name": model["name"], "title": model["title"], "model_number": model["model_number"]}
    if "shares_model_number_with" in model:
        entry["shares_model_number_with"] = model["shares_model_number_with"]
    return {**entry, "family": model["family"], "protocols": model["protocols"],
            "file": f"{model['name']}.json"}


def build_all(ref: Reference, quiet: bool) -> dict[str, str]:
    """All output files as {file name: text}."""
    available = set(ref.page_names())
    missing = [name for name in CONVERTED_PAGES if name not in available]
    if missing:
        raise SystemExit(f"convert_models: no page for {', '.join(missing)} in {ref.pages_dir}")
    pages = {}
    for name in CONVERTED_PAGES:
        try:
            pages[name] = read_page(ref, name, *classify(name))
        except ValueError as exc:
            raise SystemExit(f"convert_models: {name}: {exc}")
    for name, (donor, rows) in BORROWED_ROWS.items():
        if name in pages:
            borrow_rows(pages[name], pages[donor], rows)
    files, catalog, summary = {}, [], []
    for name, page in pages.items():
        keys = (name, *lineage(page.family, page.group))
        rule = next((RANGE_DONORS[k] for k in keys if k in RANGE_DONORS), None)
        donors = {donor: pages[donor] for donor in rule.pages} if rule else {}
        try:
            model = build_model(ref, page, donors)
            validate(model)
            deviations = cross_check(page, model)
        except (ValueError, AssertionError, KeyError) as exc:
            raise SystemExit(f"convert_models: {name}: {exc}")
        files[f"{name}.json"] = dump(model)
        catalog.append(catalog_entry(model))
        n_notes = len(model["notes"]) + sum(1 for i in model["items"] if "note" in i)
        summary.append((name, model["family"], len(model["items"]), len(model["notes"]), n_notes, deviations))
    check_model_numbers(files)
    files["catalog.json"] = dump({"models": sorted(catalog, key=lambda c: c["name"])})
    if not quiet:
        print(f"{'model':<18} {'family':<6} {'items':>5} {'model notes':>11} {'all notes':>9}  documented deviations")
        for name, fam, n_items, n_mnotes, n_notes, dev in summary:
            print(f"{name:<18} {fam:<6} {n_items:>5} {n_mnotes:>11} {n_notes:>9}  {', '.join(dev) or '-'}")
        fams = {}
        for _, fam, *_ in summary:
            fams[fam] = fams.get(fam, 0) + 1
        print("per family: " + ", ".join(f"{f} {n}" for f, n in sorted(fams.items())))
    return files


def check_model_numbers(files: dict[str, str]) -> None:
    """Two models report one number only where one of them names the other in
    shares_model_number_with (the library refuses it otherwise)."""
    models = {m["name"]: m for m in (json.loads(text) for text in files.values())}
    by_number: dict[int, str] = {}
    for name, m in sorted(models.items()):
        other = m.get("shares_model_number_with")
        if other is not None and models.get(other, {}).get("model_number") != m["model_number"]:
            raise SystemExit(f"convert_models: {name}: shares_model_number_with {other!r}, which does not "
                             f"report {m['model_number']}")
        first = by_number.setdefault(m["model_number"], name)
        if first != name and other != first and models[first].get("shares_model_number_with") != name:
            raise SystemExit(f"convert_models: {name} and {first} both report model number {m['model_number']}")


def print_not_converted(ref: Reference) -> None:
    """Names the reference pages that no model is made from (CONVERTED_PAGES)."""
    rest = sorted(set(ref.page_names()) - set(CONVERTED_PAGES))
    if rest:
        print(f"not converted: {len(rest)} reference pages have no model yet: {', '.join(rest)}")


def converter_arguments(description: str, out: Path) -> argparse.ArgumentParser:
    """The options every converter takes: --reference, --out (default `out`), --check. Shared with
    the FEETECH converter."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--reference", type=Path, default=DEFAULT_REFERENCE,
                    help="reference directory (default: ../shared/reference from the repository root)")
    ap.add_argument("--out", type=Path, default=out,
                    help=f"output directory (default: {out.relative_to(REPO_ROOT)}/)")
    ap.add_argument("--check", action="store_true",
                    help="write nothing; exit 1 listing files that differ from what is in --out")
    return ap


def main(argv=None, description: str = "") -> int:
    """Runs the converter on `argv` (sys.argv by default); returns the exit status."""
    ap = converter_arguments(description, DEFAULT_OUT)
    ap.add_argument("--quiet", action="store_true", help="no per-model summary")
    args = ap.parse_args(argv)
    files = build_all(Reference(args.reference), args.quiet or args.check)
    status = write_or_check(files, args.out, args.check, "models", "scripts/convert_models.py")
    if args.check and status == 0:
        print_not_converted(Reference(args.reference))
    return status


def write_or_check(files: dict[str, str], out: Path, check: bool, what: str, script: str) -> int:
    """Writes `files` ({name: text}) into `out`, touching only those that change; with `check`,
    writes nothing and returns 1 after naming every file of `out` that differs from `files`, is
    missing or is stale (nothing generates it). Shared with the FEETECH converter."""
    if check:
        differ, stale = differences(files, out)
        for f in differ:
            print(f"differs: {out / f}")
        for f in stale:
            print(f"not generated (stale): {out / f}")
        if differ or stale:
            print(f"run: python3 {script}")
            return 1
        print(f"{what}: {len(files)} files up to date")
        return 0
    out.mkdir(parents=True, exist_ok=True)
    for f, text in sorted(files.items()):
        path = out / f
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
    return 0
