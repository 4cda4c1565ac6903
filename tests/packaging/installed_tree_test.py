"""`cmake --install` into a temporary prefix installs the Python package with a dist-info
(docs/python.md "Installing"): Debian's python3 with PYTHONPATH at the installed site directory
imports it, its RECORD matches the files, and plain `pytest` (no -p flag, no DXLEMU_BIN, no
dxlemu on PATH) finds the fixture through the installed pytest11 entry point and the binary
installed beside it; still so after the prefix moved.
Usage: installed_tree_test.py CMAKE BUILD_DIR VERSION"""
from __future__ import annotations

import base64
import hashlib
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from user_run import require_modules, run_user_tests, user_environment

DEBIAN_PYTHON = "/usr/bin/python3"
SITE = Path("lib") / "python3" / "dist-packages"
CMAKE = BUILD = VERSION = ""


class InstalledTreeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        require_modules(DEBIAN_PYTHON, {"pytest": "python3-pytest"})
        cls._tmp = tempfile.TemporaryDirectory(prefix="dxlemu-install-")
        cls.tmp = Path(cls._tmp.name)
        cls.prefix = cls.tmp / "prefix"
        result = subprocess.run([CMAKE, "--install", BUILD, "--prefix", str(cls.prefix)],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                timeout=120)
        if result.returncode != 0:
            raise AssertionError(f"cmake --install exited {result.returncode}:\n{result.stdout}")
        cls.install_log = result.stdout

    @classmethod
    def tearDownClass(cls):
        cls._tmp.cleanup()

    def site(self, prefix: Path) -> Path:
        return prefix / SITE

    def test_the_dist_info_records_every_installed_file(self):
        site = self.site(self.prefix)
        dist_info = site / f"dxlemu-{VERSION}.dist-info"
        names = sorted(p.name for p in dist_info.iterdir())
        self.assertEqual(names, ["INSTALLER", "METADATA", "RECORD", "entry_points.txt",
                                 "top_level.txt"])
        self.assertEqual((dist_info / "top_level.txt").read_text(), "dxlemu\n")
        self.assertEqual((dist_info / "entry_points.txt").read_text(),
                         "[pytest11]\ndxlemu.pytest_plugin = dxlemu.pytest_plugin\n")
        metadata = (dist_info / "METADATA").read_text()
        self.assertTrue(metadata.startswith(
            f"Metadata-Version: 2.1\nName: dxlemu\nVersion: {VERSION}\n"), metadata[:200])
        recorded = {}
        for line in (dist_info / "RECORD").read_text().splitlines():
            path, digest, size = line.rsplit(",", 2)
            recorded[path] = (digest, size)
        installed = sorted(p.relative_to(site).as_posix() for p in site.rglob("*")
                           if p.is_file() and "__pycache__" not in p.parts)
        self.assertEqual(sorted(recorded), installed)
        self.assertIn("dxlemu/_installed.py", recorded)
        self.assertEqual(recorded.pop(f"dxlemu-{VERSION}.dist-info/RECORD"), ("", ""))
        for path, (digest, size) in recorded.items():
            data = (site / path).read_bytes()
            sha = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
            self.assertEqual((digest, size), (f"sha256={sha}", str(len(data))), path)
        # In the install manifest as well, so that what cmake installed can be listed and removed.
        self.assertIn(f"Installing: {dist_info / 'RECORD'}", self.install_log)

    def test_python_sees_the_distribution_and_its_entry_point(self):
        env = user_environment()
        env["PYTHONPATH"] = str(self.site(self.prefix))
        out = subprocess.run(
            [DEBIAN_PYTHON, "-c", "from importlib import metadata; "
             "print(metadata.version('dxlemu')); "
             "print([e.value for e in metadata.distribution('dxlemu').entry_points "
             "if e.group == 'pytest11'])"],
            cwd=self.tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(out.stdout, f"{VERSION}\n['dxlemu.pytest_plugin']\n")

    def test_plain_pytest_finds_the_fixture_and_the_installed_binary_after_a_move(self):
        moved = self.tmp / "moved"
        shutil.copytree(self.prefix, moved, symlinks=True)
        for prefix, where in ((self.prefix, "in place"), (moved, "moved")):
            with self.subTest(where):
                site = self.site(prefix)
                env = user_environment(package_dir=str(site / "dxlemu"),
                                       binary=str(prefix / "bin" / "dxlemu"), version=VERSION)
                env["PYTHONPATH"] = str(site)
                run_user_tests(DEBIAN_PYTHON, self.tmp / f"user-{where.replace(' ', '-')}", env)


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__.rsplit("\n", 1)[-1])
    CMAKE, BUILD, VERSION = sys.argv[1:4]
    del sys.argv[1:4]
    unittest.main(verbosity=2)
