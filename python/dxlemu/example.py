"""What a test script built on dxlemu needs beside the package's classes: a failed step that
says what went wrong, and a main() wrapper that turns the outcome into an exit status.

    from dxlemu.example import check, run_example

    def main() -> None:
        ...
        check(reply.error == 0, f"servo 1 should answer without error, got {reply.error}")

    if __name__ == "__main__":
        run_example(main, "ok: servo 1 answered")
"""
from __future__ import annotations

import sys
from typing import Callable

from .control import ControlError
from .daemon import DaemonError
from .protocol import CommError


class Failure(Exception):
    """A step that did not go as it should."""


def check(condition: bool, message: str) -> None:
    """Fails the script with `message` unless `condition` holds."""
    if not condition:
        raise Failure(message)


def run_example(main: Callable[[], None], success: str) -> None:
    """Runs `main`; prints `success` and returns when it does, or prints FAILED and the reason on
    stderr and exits with status 1 when a step fails or the bus, the control API or the daemon
    does not behave."""
    try:
        main()
    except (Failure, CommError, ControlError, DaemonError) as error:
        print(f"FAILED: {error}", file=sys.stderr)
        sys.exit(1)
    print(success)
