"""Writes what makes an installed copy of python/dxlemu a Python distribution (`cmake --install`,
the .deb): `dxlemu/_installed.py`, where the binary installed with the package is, and
`dxlemu-VERSION.dist-info/` (METADATA, entry_points.txt with the pytest11 entry, top_level.txt,
INSTALLER, RECORD), all taken from pyproject.toml, so that `importlib.metadata`, pip and pytest
see the package and its plugin as they would after `pip install`.

Run by CMake after it copied the package's modules (python/install/dist_info.cmake.in); prints
every file it wrote, one a line, for CMake's install manifest. Standard library only (tomllib,
Python 3.11, or tomli before it).

Usage: dist_info.py --project DIR --version V --prefix P --site-dir D --bin-dir B [--root R]
  --project   the directory of pyproject.toml (python/ of the checkout)
  --version   the version CMake installs (project(dxlemu VERSION ...)); must be pyproject's
  --prefix    the install prefix (CMAKE_INSTALL_PREFIX)
  --site-dir  where the package goes, relative to the prefix or absolute
  --bin-dir   where the dxlemu binary goes, the same way
  --root      prepended to every path written ($DESTDIR), not to the paths recorded
"""
from __future__ import annotations

import argparse
import base64
import hashlib
import os
import shutil
import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    try:
        import tomli as tomllib  # type: ignore[no-redef]
    except ModuleNotFoundError:
        sys.exit("dist_info.py: reading pyproject.toml needs Python 3.11 (tomllib) or tomli")

INSTALLER = "cmake"
"""What INSTALLER says installed the files (pip writes "pip")."""


class Failure(Exception):
    """Bad input: the message says what and where."""


def read_project(project_dir: Path, version: str) -> dict:
    """pyproject.toml's [project] table plus the packages of [tool.setuptools], checked for
    what the dist-info needs and for `version`."""
    path = project_dir / "pyproject.toml"
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise Failure(f"{path}: {error}") from error
    project = data.get("project", {})
    for key in ("name", "version", "description"):
        if not isinstance(project.get(key), str):
            raise Failure(f"{path}: [project] has no {key} string")
    if project["version"] != version:
        raise Failure(f"{path} says version {project['version']}, CMake installs {version} "
                      "(project(dxlemu VERSION ...) in CMakeLists.txt): keep them in step")
    packages = data.get("tool", {}).get("setuptools", {}).get("packages")
    if not packages:
        raise Failure(f"{path}: [tool.setuptools] lists no packages")
    project["packages"] = packages
    return project


def metadata(project: dict, project_dir: Path) -> str:
    """METADATA (core metadata 2.1): the header fields, then the readme as the description."""
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}",
             f"Version: {project['version']}", f"Summary: {project['description']}"]
    lines += [f"Classifier: {c}" for c in project.get("classifiers", [])]
    if "requires-python" in project:
        lines.append(f"Requires-Python: {project['requires-python']}")
    body = ""
    readme = project.get("readme")
    if readme:
        if not isinstance(readme, str) or not readme.endswith(".md"):
            raise Failure("pyproject.toml: readme must name a Markdown file")
        lines.append("Description-Content-Type: text/markdown")
        body = (project_dir / readme).read_text(encoding="utf-8")
    return "\n".join(lines) + "\n\n" + body


def entry_points(project: dict) -> str:
    """entry_points.txt: one INI section per group of [project.entry-points]."""
    sections = []
    for group, entries in project.get("entry-points", {}).items():
        sections.append(f"[{group}]\n" + "".join(f"{name} = {ref}\n"
                                                 for name, ref in entries.items()))
    return "\n".join(sections)


def record_line(site: Path, path: Path) -> str:
    """One RECORD row: the path relative to the site directory, its sha256 (urlsafe base64,
    no padding, as in wheels) and size."""
    data = path.read_bytes()
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{path.relative_to(site).as_posix()},sha256={digest},{len(data)}"


def under_prefix(prefix: str, directory: str) -> Path:
    """`directory` as installed: itself when absolute, else below the prefix."""
    return Path(directory) if os.path.isabs(directory) else Path(prefix) / directory


def rooted(root: str, path: Path) -> Path:
    """`path` below $DESTDIR when one is given (both absolute paths, joined as text)."""
    return Path(root + str(path)) if root else path


def install(args: argparse.Namespace) -> list[Path]:
    """Writes _installed.py and the dist-info into the installed site directory; returns the
    files written."""
    project_dir = Path(args.project)
    project = read_project(project_dir, args.version)
    site_final = under_prefix(args.prefix, args.site_dir)
    binary_final = under_prefix(args.prefix, args.bin_dir) / "dxlemu"
    site = rooted(args.root, site_final)
    modules = []
    for package in project["packages"]:
        sources = sorted((project_dir / package.replace(".", "/")).glob("*.py"))
        installed = [site / source.relative_to(project_dir) for source in sources]
        missing = [str(path) for path in installed if not path.is_file()]
        if not sources or missing:
            raise Failure(f"package {package} is not installed in {site} "
                          f"(missing: {', '.join(missing) or 'every module'})")
        modules += installed

    # Relative, so that the installed tree still finds its binary after the prefix moved.
    relative = os.path.relpath(binary_final, site_final / "dxlemu")
    marker = site / "dxlemu" / "_installed.py"
    marker.write_text('"""Written at install time (python/install/dist_info.py): the dxlemu '
                      'binary installed with this\npackage, relative to this directory."""\n'
                      f"BINARY = {relative!r}\n", encoding="utf-8")

    name = f"{project['name']}-{project['version']}.dist-info"
    for stale in site.glob(f"{project['name']}-*.dist-info"):
        if stale.name != name:  # an earlier version's, which would shadow or contradict ours
            shutil.rmtree(stale)
    dist_info = site / name
    dist_info.mkdir(exist_ok=True)
    top_level = sorted({package.split(".")[0] for package in project["packages"]})
    files = {"METADATA": metadata(project, project_dir), "entry_points.txt": entry_points(project),
             "top_level.txt": "".join(f"{t}\n" for t in top_level), "INSTALLER": f"{INSTALLER}\n"}
    written = [marker]
    for file_name, text in files.items():
        (dist_info / file_name).write_text(text, encoding="utf-8")
        written.append(dist_info / file_name)
    record = dist_info / "RECORD"
    rows = [record_line(site, path) for path in modules + written]
    rows.append(f"{record.relative_to(site).as_posix()},,")
    record.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return written + [record]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for option in ("--project", "--version", "--prefix", "--site-dir", "--bin-dir"):
        parser.add_argument(option, required=True)
    parser.add_argument("--root", default="")
    args = parser.parse_args()
    try:
        for path in install(args):
            print(path)
    except (Failure, OSError) as error:
        print(f"dist_info.py: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
