"""dxlemu.example: a failed step says why, and run_example turns it into exit status 1."""
from __future__ import annotations

import pytest

from dxlemu import CommTimeout
from dxlemu.example import Failure, check, run_example


def test_check_passes_when_the_condition_holds():
    check(True, "never seen")


def test_check_raises_the_message():
    with pytest.raises(Failure, match="servo 3 did not answer"):
        check(False, "servo 3 did not answer")


def test_run_example_prints_success(capsys):
    run_example(lambda: None, "ok: done")
    assert capsys.readouterr().out == "ok: done\n"


@pytest.mark.parametrize("error", [Failure("a step failed"), CommTimeout("no reply from 1")])
def test_run_example_fails_with_the_reason(capsys, error):
    def main() -> None:
        raise error

    with pytest.raises(SystemExit) as exited:
        run_example(main, "ok: never printed")
    assert exited.value.code == 1
    out = capsys.readouterr()
    assert out.out == ""
    assert out.err == f"FAILED: {error}\n"


def test_run_example_lets_other_errors_through():
    def main() -> None:
        raise KeyError("a bug in the script")

    with pytest.raises(KeyError):
        run_example(main, "ok: never printed")
