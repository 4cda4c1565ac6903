#!/usr/bin/env python3
"""Writes the COST of every test into tests/test_costs.cmake from what ctest recorded.

ctest keeps, in BUILD/Testing/Temporary/CTestCostData.txt, each test's average time over the runs
it made there. A fresh clone has no such record, so ctest would start the tests in the order they
were declared and might start a long one last, leaving the other core idle at the end: the table
gives it the record of an earlier run. After `scripts/test.sh` (or a ctest run in each build):

    python3 scripts/update_test_costs.py build/san build/test

A test both builds ran takes the first directory's figure. Costs are rounded to 0.1 s, and a
test no directory ran keeps the cost it had.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

TABLE = Path(__file__).resolve().parents[1] / "tests" / "test_costs.cmake"
BEGIN = "set(DXLEMU_TEST_COSTS\n"
END = ")\n"


def recorded(build: Path) -> dict[str, float]:
    """name -> average seconds from BUILD's ctest cost record (empty when it has none)."""
    path = build / "Testing" / "Temporary" / "CTestCostData.txt"
    costs: dict[str, float] = {}
    if not path.is_file():
        sys.exit(f"update_test_costs: {path} does not exist: run ctest in {build} first")
    for line in path.read_text().splitlines():
        if line.startswith("---"):
            break  # the failed tests follow
        name, _runs, cost = line.rsplit(" ", 2)
        costs[name] = float(cost)
    return costs


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit("usage: update_test_costs.py BUILD_DIR...")
    text = TABLE.read_text()
    start = text.index(BEGIN) + len(BEGIN)
    stop = text.index(END, start)
    costs = dict(re.findall(r"^\s*(\S+) ([0-9.]+)$", text[start:stop], re.MULTILINE))
    for build in reversed(sys.argv[1:]):
        for name, cost in recorded(Path(build)).items():
            if " " in name:
                sys.exit(f"update_test_costs: a test name with a space cannot be costed: {name!r}")
            costs[name] = f"{max(cost, 0.1):.1f}"
    rows = "".join(f"  {name} {cost}\n" for name, cost in sorted(costs.items()))
    TABLE.write_text(text[:start] + rows + text[stop:])
    print(f"update_test_costs: {len(costs)} tests in {TABLE}")


if __name__ == "__main__":
    main()
