"""`pip install --no-build-isolation ./python` (docs/python.md "Installing") into a scratch venv
with no index at all, then plain `pytest` (no -p flag, no PYTHONPATH) finds the `dxlemu` fixture
through the installed pytest11 entry point, and the package the build of the checkout it was
installed from. Also with `-p dxlemu.pytest_plugin` and a conftest.py naming the plugin, as
before installing: the plugin is loaded once, not refused as registered twice.

The checkout is a copy of python/ beside a build/emulator/dxlemu that links to $DXLEMU_BIN (the
binary under test); the venv is Debian's python3 with --system-site-packages, whose setuptools,
wheel and pytest are Debian's (python3-venv, python3-setuptools, python3-wheel, python3-pytest).
Usage: DXLEMU_BIN=... pip_install_test.py VERSION"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from user_run import require_modules, run_user_tests, user_environment

SOURCE = Path(__file__).resolve().parents[2] / "python"
DEBIAN_PYTHON = "/usr/bin/python3"
VERSION = ""


def run(command: list[str], **options) -> str:
    """Runs `command`, returning its output; AssertionError with the output when it fails."""
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=300, **options)
    if result.returncode != 0:
        raise AssertionError(f"{' '.join(command)} exited {result.returncode}:\n{result.stdout}")
    return result.stdout


class PipInstallTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        binary = os.environ.get("DXLEMU_BIN")
        if not binary or not os.path.isfile(binary):
            raise AssertionError("DXLEMU_BIN must name the dxlemu binary under test")
        require_modules(DEBIAN_PYTHON, {"ensurepip": "python3-venv", "pytest": "python3-pytest",
                                        "setuptools": "python3-setuptools",
                                        "wheel": "python3-wheel"})
        cls._tmp = tempfile.TemporaryDirectory(prefix="dxlemu-pip-")
        cls.tmp = Path(cls._tmp.name)
        checkout = cls.tmp / "checkout"
        shutil.copytree(SOURCE, checkout / "python", ignore=shutil.ignore_patterns(
            "tests", "build", "*.egg-info", "__pycache__"))
        cls.binary = checkout / "build" / "emulator" / "dxlemu"
        cls.binary.parent.mkdir(parents=True)
        cls.binary.symlink_to(os.path.abspath(binary))
        venv = cls.tmp / "venv"
        run([DEBIAN_PYTHON, "-m", "venv", "--system-site-packages", str(venv)])
        cls.python = str(venv / "bin" / "python")
        # PIP_NO_INDEX: were anything to be downloaded, the install would fail here.
        env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
        env.pop("PYTHONPATH", None)
        cls.pip_output = run([cls.python, "-m", "pip", "install", "--no-build-isolation",
                              "./python"], cwd=checkout, env=env)
        cls.package_dir = run([cls.python, "-c", "import dxlemu, os; "
                               "print(os.path.dirname(dxlemu.__file__))"],
                              cwd=cls.tmp, env=user_environment()).strip()

    @classmethod
    def tearDownClass(cls):
        cls._tmp.cleanup()

    def test_pip_installed_the_version_into_the_venv(self):
        self.assertIn(f"Successfully installed dxlemu-{VERSION}", self.pip_output)
        self.assertTrue(self.package_dir.startswith(str(self.tmp / "venv")), self.package_dir)

    def test_plain_pytest_finds_the_fixture_and_the_checkout_build(self):
        env = user_environment(package_dir=self.package_dir, binary=str(self.binary),
                               version=VERSION)
        run_user_tests(self.python, self.tmp / "plain", env)

    def test_dash_p_and_a_conftest_load_the_plugin_once(self):
        env = user_environment(package_dir=self.package_dir, binary=str(self.binary),
                               version=VERSION)
        run_user_tests(self.python, self.tmp / "flagged", env, conftest=True,
                       args=("-p", "dxlemu.pytest_plugin"))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__.rsplit("\n", 1)[-1])
    VERSION = sys.argv.pop(1)
    unittest.main(verbosity=2)
