"""Where the dxlemu binary that belongs to this copy of the package is, for `find_binary` when
neither the caller, $DXLEMU_BIN nor PATH names one: the binary installed with the package
(`cmake --install`, the .deb), or the build of the checkout the package comes from, whether it
runs from that checkout or pip installed it from there."""
from __future__ import annotations

import json
import os
from importlib import metadata
from pathlib import Path
from urllib.parse import urlparse
from urllib.request import url2pathname

_PACKAGE_DIR = Path(os.path.abspath(os.path.dirname(__file__)))
_CHECKOUT_BINARY = Path("build") / "emulator" / "dxlemu"
"""The build's binary, relative to the checkout's top directory."""


def installed_binary() -> Path | None:
    """The binary installed with the package: `_installed.py`, written at install time
    (python/install/dist_info.py), holds its path relative to the package's directory, so that
    a moved prefix still finds it. None for a checkout's or a pip-installed copy."""
    try:
        from ._installed import BINARY
    except ImportError:
        return None
    return Path(os.path.normpath(_PACKAGE_DIR / BINARY))


def _pip_source() -> Path | None:
    """The directory pip installed this copy from (`pip install ./python`), as the copy's
    direct_url.json (PEP 610) records it; None for other installs."""
    for dist in metadata.distributions(name="dxlemu"):
        try:
            if Path(dist.locate_file("dxlemu/__init__.py")).resolve() != \
                    (_PACKAGE_DIR / "__init__.py").resolve():
                continue  # another copy's metadata, earlier or later on sys.path
            info = json.loads(dist.read_text("direct_url.json") or "{}")
        except (OSError, ValueError):
            continue
        url = info.get("url", "")
        if "dir_info" in info and url.startswith("file:"):
            return Path(url2pathname(urlparse(url).path))
    return None


def checkout_binaries() -> list[Path]:
    """build/emulator/dxlemu of the checkout this package sits in (its python/dxlemu, beside
    python/pyproject.toml), then of the checkout pip installed it from (whose python/
    direct_url.json names)."""
    here = _PACKAGE_DIR.resolve().parent
    places = [here.parent / _CHECKOUT_BINARY] if (here / "pyproject.toml").is_file() else []
    source = _pip_source()
    if source is not None:
        places.append(source.parent / _CHECKOUT_BINARY)
    return places
