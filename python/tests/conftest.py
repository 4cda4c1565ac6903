"""The package's own tests: `python/` on sys.path, the `dxlemu` fixture enabled."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

pytest_plugins = ["dxlemu.pytest_plugin"]
