"""DynamixelSDK's control tables agree with models/ (ctest models.sdk_control_tables_agree).

For every model both know: the model number is dynamixel.model's, and every item an SDK file
names has the same address and size in the model (sdk_pairing.py says which file each model's
firmware is compared with, sdk_names.py which item an SDK name stands for); each `_fwNN` table
(xl330_m288_fw52.model) of a model is compared with the model's firmware variant for NN, and one
the model has no variant for fails. A difference fails
unless a `sdk-control-tables:` note of the model explains it (sdk_notes.py). Prints what was
compared and a summary; exits 1 on any unexplained difference or when the reference is missing.

    python3 tests/models/sdk_control_tables_test.py [--reference DIR] [--models DIR] [-v]

Standard library only. The reference is ../shared/reference beside the checkout."""
import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from model_views import load_models  # noqa: E402
from sdk_compare import check  # noqa: E402
from sdk_pairing import pair  # noqa: E402
from sdk_tables import REGISTRY, parse_model_file, parse_registry  # noqa: E402

ROOT = HERE.parent.parent
SDK_DIR = "sdk-control-tables"


def load_sdk(sdk_dir: Path):
    """(registry, file name -> SdkFile) of sdk_dir; every registered file must be there."""
    registry = parse_registry((sdk_dir / REGISTRY).read_text(encoding="utf-8"))
    files = {}
    for path in sorted(sdk_dir.glob("*.model")):
        if path.name != REGISTRY:
            files[path.name] = parse_model_file(path.read_text(encoding="utf-8"), path.name)
    missing = sorted(f for f in registry if f not in files)
    if missing:
        raise ValueError(f"{REGISTRY} lists {', '.join(missing)}, which {sdk_dir} does not have")
    return registry, files


def run(reference: Path, models_dir: Path, out, verbose: bool = False) -> int:
    """The whole cross-check, printed to `out`; 0 when everything agrees or is explained."""
    sdk_dir = reference / SDK_DIR
    if not (sdk_dir / REGISTRY).is_file():
        print(f"FAIL: no {sdk_dir / REGISTRY}: the cross-check needs {SDK_DIR}/ in the reference "
              f"(../shared/reference beside the checkout)", file=out)
        return 1
    try:
        registry, files = load_sdk(sdk_dir)
        models = load_models(models_dir)
    except (OSError, ValueError) as e:
        print(f"FAIL: {e}", file=out)
        return 1
    pairing = pair(registry, files, models)
    # A firmware table whose model pairs is the layout a servo reporting that firmware has: the
    # model must have the variant, or a client that reads its firmware gets another table.
    for file, why in pairing.not_compared:
        if files[file].last_firmware is not None and files[file].base_file in pairing.pairs:
            pairing.errors.append(f"{file}: {why}")
    result = check(pairing.comparisons, reference / "control-tables", models)
    report(pairing, result, len({f.base_file for f in files.values()}), len(models), out, verbose)
    failed = result.unexplained or result.note_errors or pairing.errors
    print("FAIL" if failed else "OK", file=out)
    return 1 if failed else 0


def report(pairing, result, sdk_models: int, model_files: int, out, verbose: bool):
    """What was compared, the lists, the differences and the summary."""
    per = {}
    for c in pairing.comparisons:
        per.setdefault((c.sdk.file, c.view.label), [c, 0])
    for d in result.differences:
        per[(d.sdk_file, d.view)][1] += 1
    print(f"Compared ({len(pairing.comparisons)} model views with an SDK file):", file=out)
    for (file, label), (c, n) in sorted(per.items()):
        if verbose or n:
            print(f"  {file:<24} {label:<44} {len(c.sdk.items):>3} items, {n} differences; by {c.how}",
                  file=out)
    if not verbose:
        print("  (those without differences: -v)", file=out)
    sections = [
        ("Not compared", [f"{f}: {why}" for f, why in pairing.not_compared]),
        ("Default firmware a client reads otherwise (informational until the model has variants)",
         pairing.firmware_info),
        ("SDK models with no model file yet (informational)",
         [f"{f} ({'unregistered' if n is None else n})" for f, n in pairing.sdk_without_model]),
        ("Models with no SDK file (informational)",
         [f"{m} ({n}): {why}" for m, n, why in pairing.models_without_sdk]),
        ("Explained differences",
         [f"{d.line()}\n      explained by: {d.explained_by.note}" for d in result.explained]),
        ("Pairing errors", pairing.errors),
        ("Notes in error", result.note_errors),
        ("UNEXPLAINED DIFFERENCES", [d.line() for d in result.unexplained]),
    ]
    for title, lines in sections:
        if lines:
            print(f"{title} ({len(lines)}):", file=out)
            for line in lines:
                print(f"  {line}", file=out)
    print(f"Summary: {len(pairing.pairs)} models both sources know ({sdk_models} SDK models, "
          f"{model_files} model files; {len(pairing.shared)} more by a shared model number), "
          f"{result.compared_items} items compared in {len(pairing.comparisons)} comparisons, "
          f"{len(result.explained)} explained differences, {len(result.unexplained)} unexplained; "
          f"{len(pairing.not_compared)} SDK files not compared, {len(pairing.sdk_without_model)} "
          f"SDK models without a model file yet.", file=out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", type=Path, default=ROOT.parent / "shared" / "reference")
    parser.add_argument("--models", type=Path, default=ROOT / "models")
    parser.add_argument("-v", "--verbose", action="store_true", help="list every comparison")
    args = parser.parse_args(argv)
    return run(args.reference, args.models, sys.stdout, args.verbose)


if __name__ == "__main__":
    sys.exit(main())
