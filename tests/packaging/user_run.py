"""What both packaging tests do once the package is installed: run the tests of user_tests/ the
way a user would, with plain `pytest` in a directory of their own, and check that they passed.
Standard library only."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

USER_TESTS = Path(__file__).resolve().parent / "user_tests"
TEST_COUNT = 3
"""Tests in user_tests/test_installed_plugin.py: a run must pass them all."""


def require_modules(python: str, packages: dict[str, str]) -> None:
    """Raises AssertionError naming the Debian package of every module (key) `python` cannot
    import: the packaging tests need Debian's, which scripts/setup.sh installs."""
    missing = [package for module, package in packages.items()
               if subprocess.run([python, "-c", f"import {module}"], stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL).returncode != 0]
    if missing:
        raise AssertionError(f"{python} lacks Debian package(s) {', '.join(missing)}")


def path_without_dxlemu() -> str:
    """$PATH minus every directory holding a `dxlemu`, so that the package has to find its
    binary itself (a wrapper such as valgrind stays reachable)."""
    keep = [d for d in os.environ.get("PATH", "").split(os.pathsep)
            if d and not os.path.exists(os.path.join(d, "dxlemu"))]
    return os.pathsep.join(keep)


def user_environment(**expected: str) -> dict[str, str]:
    """The environment of a user's pytest run: no DXLEMU_BIN, no PYTHONPATH (the caller adds
    one where a user would), no plugins named by environment, PATH without dxlemu; the
    EXPECTED_* variables the user tests check."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("DXLEMU_BIN", "PYTHONPATH", "PYTEST_PLUGINS", "PYTEST_ADDOPTS")}
    env["PATH"] = path_without_dxlemu()
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env.update({f"EXPECTED_{k.upper()}": v for k, v in expected.items()})
    return env


def run_user_tests(python: str, directory: Path, env: dict[str, str], *, conftest: bool = False,
                   args: tuple[str, ...] = ()) -> str:
    """Copies the user tests into `directory` (with a conftest.py enabling the plugin the old
    way when `conftest`), runs `python -m pytest ARGS` there and returns its output; raises
    AssertionError unless every test passed."""
    directory.mkdir(parents=True)
    shutil.copy(USER_TESTS / "test_installed_plugin.py", directory)
    if conftest:
        (directory / "conftest.py").write_text('pytest_plugins = ["dxlemu.pytest_plugin"]\n')
    command = [python, "-m", "pytest", "-v", "-p", "no:cacheprovider", *args]
    result = subprocess.run(command, cwd=directory, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, timeout=240)
    summary = re.search(r"=+ (.*) in [0-9.]+s", result.stdout)
    if result.returncode != 0 or summary is None or summary.group(1) != f"{TEST_COUNT} passed":
        raise AssertionError(f"{' '.join(command)} in {directory} exited {result.returncode}, "
                             f"not {TEST_COUNT} passed:\n{result.stdout}")
    return result.stdout
