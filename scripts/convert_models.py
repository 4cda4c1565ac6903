#!/usr/bin/env python3
"""Convert the offline ROBOTIS e-Manual control-table pages into dxlemu model files.

Usage:
    python3 scripts/convert_models.py [--reference DIR] [--out DIR] [--check] [--quiet]

Reads the pages of CONVERTED_PAGES in DIR/control-tables/*.md (default DIR: ../shared/reference
relative to the repository root), the shared description blocks in DIR/control-tables/includes/
and DIR/models.tsv, and writes OUT/<name>.json for each plus OUT/catalog.json (default OUT:
models/). Nothing else is written; the pages it does not convert yet are named. The format is
docs/model-format.md; the JSON Schema is models/schema/model.schema.json.

--check regenerates everything in memory and exits 1, naming the files that differ from what is
on disk (missing, changed or stale), without writing anything. CI uses it.

Everything the pages do not state is a decision of the converter, kept as data in
model_converter/decisions/; each one is written into the model's `notes` (model level) or the
item's `note`, so a reviewer can read the JSON and see why. Facts that come from outside the
offline reference (a few e-Manual includes that were not copied, motor specifications, the boot
time) carry the public URL they were read from.

The converter is the package model_converter/ beside this file (its __init__.py, and
docs/model-format.md "The converter, module by module", say which module does what); this file
only runs it. Standard library only.
"""

import sys
from pathlib import Path

# Running this file puts its directory on sys.path; importing it from elsewhere may not.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from model_converter.cli import main  # noqa: E402  (needs the path above)

if __name__ == "__main__":
    sys.exit(main(description=__doc__.split("\n\n")[0]))
