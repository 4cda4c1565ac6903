"""Emulator and DaemonProcess: start, readiness, ports, stop, and failures with stderr."""
import json
import os
import re

import pytest

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
    emulator = Emulator(timing="fast")
    link, directory = emulator.link, emulator.directory
    assert emulator.stop() == 0
    assert not os.path.lexists(link) and not os.path.exists(directory)
    assert "stopping on the control API's shutdown" in emulator.stderr
    assert emulator.stop() == 0  # a second stop does nothing


def test_the_context_manager_stops_the_daemon():
    with Emulator(timing="fast") as emulator:
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
    with Emulator(config=config, timing="fast") as emulator:
        assert list(emulator.ports) == ["arm", "legs"]
        assert emulator.port("legs").link == str(tmp_path / "legs")
        with emulator.client("legs", baud=1000000, protocol=1) as legs:
            assert legs.ping(7).error == 0


def test_the_binary_comes_from_the_argument_then_the_environment(monkeypatch):
    assert find_binary("/x/dxlemu") == "/x/dxlemu"
    monkeypatch.setenv("DXLEMU_BIN", "/y/dxlemu")
    assert find_binary() == "/y/dxlemu"


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
