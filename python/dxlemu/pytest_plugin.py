"""pytest fixture `dxlemu`: a running emulator on a temporary bus for one test, stopped after it.

Once the package is installed (pip, `cmake --install`, the .deb) pytest loads it by itself,
through the package's pytest11 entry point, named `dxlemu.pytest_plugin` like this module so
that the ways of enabling it uninstalled still work beside it: `pytest -p dxlemu.pytest_plugin`,
or `pytest_plugins = ["dxlemu.pytest_plugin"]` in the top-level conftest.py.

By default the bus is the daemon's default (three XM430-W350, IDs 1 ~ 3, 57,600 bit/s) with
`--timing fast`; a test changes that with the `dxlemu` marker, whose keyword arguments go to
dxlemu.Emulator:

    @pytest.mark.dxlemu(servos=["xm430-w350:1-4"], timing="manual")
    def test_something(dxlemu):
        dxlemu.control.clock_step(ms=100)

The binary is found as dxlemu.find_binary does ($DXLEMU_BIN, PATH, the one installed with the
package, the checkout's build), or given with `--dxlemu-bin PATH`.
"""
from __future__ import annotations

from typing import Iterator

import pytest

from .daemon import Emulator

DEFAULTS = {"timing": "fast"}
"""What the fixture passes to Emulator unless the test's marker says otherwise."""


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--dxlemu-bin", default=None, help="the dxlemu binary the fixture starts")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "dxlemu(**options): options of the dxlemu fixture's "
                                       "Emulator (servos, timing, seed, config, ...)")


@pytest.fixture
def dxlemu(request: pytest.FixtureRequest) -> Iterator[Emulator]:
    """An Emulator started for this test (options from the `dxlemu` marker), stopped after it.
    A daemon that did not exit cleanly fails the test."""
    options = dict(DEFAULTS)
    marker = request.node.get_closest_marker("dxlemu")
    if marker is not None:
        options.update(marker.kwargs)
    options.setdefault("binary", request.config.getoption("--dxlemu-bin"))
    emulator = Emulator(**options)
    try:
        yield emulator
    finally:
        code = emulator.stop()
    if code != 0:
        pytest.fail(f"dxlemu exited with status {code}:\n{emulator.stderr}")
