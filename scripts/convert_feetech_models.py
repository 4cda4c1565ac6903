#!/usr/bin/env python3
"""Convert the offline FEETECH memory tables into dxlemu model files.

Usage:
    python3 scripts/convert_feetech_models.py [--reference DIR] [--out DIR] [--check]

Reads DIR/feetech/<model>.md (default DIR: ../shared/reference relative to the repository root)
for every model of feetech_converter/decisions.py and writes OUT/<name>.json (default OUT:
models/feetech/). --check writes nothing and exits 1 naming every file that differs from what it
would write. The format is docs/model-format.md; docs/feetech.md "Models" says what the files
hold and which choices the converter makes (each is in the file's notes or the item's note).

The converter is the package feetech_converter/ beside this file; it reads Markdown with the
DYNAMIXEL converter's reader (model_converter/markdown.py). Standard library only.
"""

import sys
from pathlib import Path

# Running this file puts its directory on sys.path; importing it from elsewhere may not.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from feetech_converter.cli import main  # noqa: E402  (needs the path above)

if __name__ == "__main__":
    sys.exit(main(description=__doc__.split("\n\n")[0]))
