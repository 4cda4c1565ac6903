#!/usr/bin/env python3
"""Fault injection example: a servo is unplugged and plugged back in; the controller must notice
it went silent, wait for it to come back, and re-apply its settings, lost with the power.

    python3 scripts/examples/unplug_replug.py          # exit 0: every step held

Copy it and replace `Controller` with your own controller code. It needs only the standard
library and the dxlemu package (python/ of the dxlemu checkout: adjust the sys.path line below,
or set PYTHONPATH). The binary is $DXLEMU_BIN, else `dxlemu` on PATH, else the checkout's build.

The steps:
1. dxlemu runs the default bus (three XM430-W350, IDs 1 ~ 3, Protocol 2.0).
2. The controller configures every servo (torque on, a goal position).
3. The script unplugs servo 2 (control API `servo.detach`): its pings time out, the others
   still answer; the controller marks it lost.
4. The script plugs it back in (`servo.attach`): the servo powers on and is silent while it
   boots (about 0.4 s), then answers again.
5. The controller sees it back, finds Torque Enable 0 (RAM is lost with the power) and
   configures it again: torque on, goal position, and the servo moves there.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))  # the dxlemu package

from dxlemu import Client, CommTimeout, Emulator  # noqa: E402
from dxlemu.example import check, run_example  # noqa: E402

# XM430-W350 control table (e-Manual; models/xm430-w350.json).
TORQUE_ENABLE, GOAL_POSITION, PRESENT_POSITION = 64, 116, 132

SERVOS = (1, 2, 3)
UNPLUGGED = 2
GOALS = {1: 1500, 2: 2500, 3: 3000}
BOOT_S = 0.4  # the model's boot time
COMEBACK_TIMEOUT_S = 3.0
POSITION_TOLERANCE = 20  # pulses
MOVE_TIMEOUT_S = 5.0


class Controller:
    """The controller under test, reduced to what matters here: it configures its servos, pings
    them, marks the silent ones lost and configures a lost servo again when it answers."""

    def __init__(self, client: Client, goals: dict[int, int]):
        self.client = client
        self.goals = goals
        self.lost: set[int] = set()
        self.reconfigured: list[int] = []

    def configure(self, servo: int) -> None:
        """Torque on and the servo's goal position, as after any power-on."""
        for address, value, size in ((TORQUE_ENABLE, 1, 1), (GOAL_POSITION, self.goals[servo], 4)):
            reply = self.client.write_int(servo, address, value, size)
            check(reply.error == 0,
                  f"servo {servo}: write of {address} refused: 0x{reply.error:02x}")

    def check_servos(self) -> None:
        """One round of pings. A silent servo is lost; a lost servo that answers again had its
        power cut: if its torque is off, it is configured again."""
        for servo in self.goals:
            try:
                self.client.ping(servo)
            except CommTimeout:
                self.lost.add(servo)
                continue
            if servo in self.lost:
                self.lost.discard(servo)
                if self.client.read(servo, TORQUE_ENABLE, 1).value == 0:
                    self.configure(servo)
                    self.reconfigured.append(servo)


def wait_for_position(client: Client, servo: int, goal: int) -> None:
    """Waits until the servo is within POSITION_TOLERANCE of `goal`."""
    deadline = time.monotonic() + MOVE_TIMEOUT_S
    while abs(client.read(servo, PRESENT_POSITION, 4).signed - goal) > POSITION_TOLERANCE:
        check(time.monotonic() < deadline, f"servo {servo} did not reach {goal}")
        time.sleep(0.02)


def main() -> None:
    with Emulator(timing="fast") as emulator, emulator.client(timeout=0.3) as client:
        control = emulator.control
        controller = Controller(client, GOALS)
        for servo in SERVOS:
            controller.configure(servo)
        controller.check_servos()
        check(not controller.lost, f"every servo should answer, lost: {controller.lost}")

        control.detach(UNPLUGGED)
        print(f"servo {UNPLUGGED} unplugged")
        for _ in range(3):
            controller.check_servos()
        check(controller.lost == {UNPLUGGED}, f"only servo 2 should be lost, got {controller.lost}")

        control.attach(UNPLUGGED)
        plugged = time.monotonic()
        print(f"servo {UNPLUGGED} plugged back in")
        while controller.lost:
            check(time.monotonic() - plugged < COMEBACK_TIMEOUT_S, "servo 2 never came back")
            controller.check_servos()
        silent = time.monotonic() - plugged
        print(f"controller: servo {UNPLUGGED} answers again after {silent:.2f} s")
        check(silent >= BOOT_S * 0.75, f"servo 2 answered {silent:.2f} s after power-on, "
                                       f"before its boot time ({BOOT_S} s)")
        check(controller.reconfigured == [UNPLUGGED], "the controller should have re-applied "
              f"servo 2's settings, got {controller.reconfigured}")
        check(client.read(UNPLUGGED, TORQUE_ENABLE, 1).value == 1, "servo 2's torque should be on")
        wait_for_position(client, UNPLUGGED, GOALS[UNPLUGGED])
        for servo in SERVOS:
            wait_for_position(client, servo, GOALS[servo])
        check(emulator.stop() == 0, "dxlemu should stop cleanly")


if __name__ == "__main__":
    run_example(main, "ok: the unplugged servo was noticed, came back after boot, and was configured again")
