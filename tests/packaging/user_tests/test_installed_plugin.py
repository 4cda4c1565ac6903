"""A user's tests against an installed dxlemu package: the packaging tests copy this file into
an empty directory and run plain `pytest` there (no -p flag, no conftest.py, no PYTHONPATH to
the checkout, no DXLEMU_BIN). EXPECTED_PACKAGE_DIR, EXPECTED_BINARY and EXPECTED_VERSION say
which copy of the package, which binary and which version they must find."""
import os
from pathlib import Path

import pytest

import dxlemu as package


def test_the_installed_copy_is_imported():
    assert Path(package.__file__).resolve().parent == \
        Path(os.environ["EXPECTED_PACKAGE_DIR"]).resolve()


def test_the_binary_is_found_without_being_named():
    assert "DXLEMU_BIN" not in os.environ
    assert package.find_binary() == os.environ["EXPECTED_BINARY"]


@pytest.mark.dxlemu(timing="manual")  # the Ping's reply at once, never dropped as late
def test_the_fixture_comes_from_the_installed_entry_point(dxlemu, pytestconfig):
    loaded = {dist.metadata["Name"]: dist.version
              for _, dist in pytestconfig.pluginmanager.list_plugin_distinfo()}
    assert loaded.get("dxlemu") == os.environ["EXPECTED_VERSION"], loaded
    assert dxlemu.process.binary == os.environ["EXPECTED_BINARY"]
    with dxlemu.client() as client:
        assert client.ping(1).error == 0
