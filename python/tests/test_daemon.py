"""Emulator and DaemonProcess: start, readiness, ports, stop, and failures with stderr."""
import json
import os
import re
import sys
import types
from pathlib import Path

import pytest

import dxlemu._places
from dxlemu import DaemonError, DaemonProcess, Emulator, find_binary


def test_the_fixture_gives_a_ready_default_bus_in_its_own_directory(dxlemu):
    port = dxlemu.port("dxl0")
    assert port.link == os.path.join(dxlemu.directory, "dxl0")
    assert os.path.realpath(port.link) == port.pty
    assert [servo["id"] for servo in port.servos] == [1, 2, 3]
    assert dxlemu.link == port.link and dxlemu.running


@pytest.mark.dxlemu(servos=["xm430-w350:7", "ax-12a:10"], timing="manual")
def test_the_marker_passes_servos_and_timing(dxlemu):
    assert [servo["id"] for servo in dxlemu.port().servos] == [7, 10]
    assert dxlemu.control.clock_now() == 0


def test_stop_shuts_down_cleanly_and_removes_link_socket_and_directory():
    emulator = Emulator(timing="manual")
    link, directory = emulator.link, emulator.directory
    assert emulator.stop() == 0
    assert not os.path.lexists(link) and not os.path.exists(directory)
    assert "stopping on the control API's shutdown" in emulator.stderr
    assert emulator.stop() == 0  # a second stop does nothing


def test_the_context_manager_stops_the_daemon():
    with Emulator(timing="manual") as emulator:
        process = emulator.process
    assert not process.running and process.proc.returncode == 0


def test_a_daemon_that_refuses_its_options_raises_with_its_stderr():
    with pytest.raises(DaemonError) as error:
        Emulator(servos=["xm999:1"])
    assert error.value.returncode == 2
    assert 'unknown model "xm999"' in error.value.stderr
    assert 'unknown model "xm999"' in str(error.value)


def test_a_config_with_two_ports_is_ready_once_both_are(tmp_path):
    config = tmp_path / "bus.json"
    config.write_text(json.dumps({"ports": [
        {"name": "arm", "link": str(tmp_path / "arm"),
         "servos": [{"model": "xm430-w350", "id": 1}]},
        {"name": "legs", "link": str(tmp_path / "legs"),
         "servos": [{"model": "ax-12a", "id": 7}]}]}))
    with Emulator(config=config, timing="manual") as emulator:
        assert list(emulator.ports) == ["arm", "legs"]
        assert emulator.port("legs").link == str(tmp_path / "legs")
        with emulator.client("legs", baud=1000000, protocol=1) as legs:
            assert legs.ping(7).error == 0


def test_the_binary_comes_from_the_argument_then_the_environment(monkeypatch):
    assert find_binary("/x/dxlemu") == "/x/dxlemu"
    monkeypatch.setenv("DXLEMU_BIN", "/y/dxlemu")
    assert find_binary() == "/y/dxlemu"


def _executable(path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\n")
    path.chmod(0o755)
    return path


def _installed_at(monkeypatch, binary: Path) -> None:
    """This copy of the package as `cmake --install` leaves it: an _installed.py naming
    `binary` relative to the package's directory."""
    package_dir = Path(dxlemu._places.__file__).parent
    module = types.ModuleType("dxlemu._installed")
    module.BINARY = os.path.relpath(binary, package_dir)
    monkeypatch.setitem(sys.modules, "dxlemu._installed", module)


def test_after_the_environment_come_path_then_the_installed_binary(monkeypatch, tmp_path):
    monkeypatch.delenv("DXLEMU_BIN", raising=False)
    installed = _executable(tmp_path / "prefix" / "bin" / "dxlemu")
    _installed_at(monkeypatch, installed)
    on_path = _executable(tmp_path / "path" / "dxlemu")
    monkeypatch.setenv("PATH", str(on_path.parent))
    assert find_binary() == str(on_path)
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    assert find_binary() == str(installed)


def test_then_the_checkout_build_and_a_missing_one_names_every_place(monkeypatch, tmp_path):
    monkeypatch.delenv("DXLEMU_BIN", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    installed = tmp_path / "prefix" / "bin" / "dxlemu"  # recorded, but not there
    _installed_at(monkeypatch, installed)
    checkout = Path(dxlemu._places.__file__).resolve().parents[2]
    monkeypatch.setattr(dxlemu._places, "_CHECKOUT_BINARY", Path("no-build") / "dxlemu")
    with pytest.raises(DaemonError) as error:
        find_binary()
    assert f"looked for {installed}, {checkout / 'no-build' / 'dxlemu'}" in str(error.value)
    # Any file stands for the checkout's build here: the test may run from a build elsewhere.
    monkeypatch.setattr(dxlemu._places, "_CHECKOUT_BINARY", Path("python") / "pyproject.toml")
    assert find_binary() == str(checkout / "python" / "pyproject.toml")


def test_a_missing_binary_is_a_daemon_error_naming_its_path(monkeypatch):
    monkeypatch.delenv("DXLEMU_WRAPPER", raising=False)  # the binary itself is run
    with pytest.raises(DaemonError) as error:
        DaemonProcess([], binary="/nonexistent/dxlemu")
    assert type(error.value) is DaemonError  # not subprocess's FileNotFoundError
    assert str(error.value).startswith(
        "cannot run /nonexistent/dxlemu: No such file or directory")
    assert error.value.returncode is None and error.value.stderr == ""


def test_a_binary_that_is_not_executable_is_a_daemon_error_naming_its_path(tmp_path,
                                                                          monkeypatch):
    monkeypatch.delenv("DXLEMU_WRAPPER", raising=False)
    binary = tmp_path / "dxlemu"
    binary.write_text("not a program\n")  # mode 0644
    with pytest.raises(DaemonError, match=re.escape(f"cannot run {binary}: Permission denied")):
        Emulator(binary=binary)
