#!/usr/bin/env python3
"""Fault injection example: a servo is unplugged and plugged back in; the controller must notice
it went silent, wait for it to come back, and re-apply its settings, lost with the power.

    python3 scripts/examples/unplug_replug.py          # exit 0: every step held

Copy it and replace `Controller` with your own controller code. It needs only the standard
library and the dxlemu package (python/ of the dxlemu checkout: adjust the sys.path line below,
or set PYTHONPATH). The binary is $DXLEMU_BIN, else `dxlemu` on PATH, else the checkout's build.

The steps:
1. dxlemu runs the default bus (three XM430-W350, IDs 1 ~ 3, Protocol 2.0) under
   `--timing manual`: simulated time (the boot time, the moves) passes only when the script
   steps it between the controller's rounds, so what the controller sees does not depend on how
   busy the machine is, and replies are never dropped as late.
2. The controller configures every servo (torque on, a goal position).
3. The script unplugs servo 2 (control API `servo.detach`): its pings time out, the others
   still answer; the controller marks it lost.
4. The script plugs it back in (`servo.attach`): the servo powers on and is silent while it
   boots (0.4 s), then answers again; the script steps the clock 0.1 s between the
   controller's rounds, so the controller must find it back at the round at 0.4 s.
5. The controller sees it back, finds Torque Enable 0 (RAM is lost with the power) and
   configures it again: torque on, goal position, and the servo moves there.
"""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))  # the dxlemu package

from dxlemu import Client, CommTimeout, Control, Emulator  # noqa: E402
from dxlemu.example import check, run_example  # noqa: E402

# XM430-W350 control table (e-Manual; models/xm430-w350.json).
TORQUE_ENABLE, GOAL_POSITION, PRESENT_POSITION = 64, 116, 132

SERVOS = (1, 2, 3)
UNPLUGGED = 2
GOALS = {1: 1500, 2: 2500, 3: 3000}
BOOT_MS = 400  # the model's boot time
ROUND_MS = 100  # simulated time between two rounds of the controller
COMEBACK_TIMEOUT_MS = 3000
POSITION_TOLERANCE = 20  # pulses
MOVE_STEP_MS = 20
MOVE_TIMEOUT_MS = 5000


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


def wait_for_position(control: Control, client: Client, servo: int, goal: int) -> None:
    """Steps the clock until the servo is within POSITION_TOLERANCE of `goal`, for at most
    MOVE_TIMEOUT_MS of simulated time."""
    waited = 0
    while abs(client.read(servo, PRESENT_POSITION, 4).signed - goal) > POSITION_TOLERANCE:
        check(waited < MOVE_TIMEOUT_MS, f"servo {servo} did not reach {goal}")
        control.clock_step(ms=MOVE_STEP_MS)
        waited += MOVE_STEP_MS


def main() -> None:
    with Emulator(timing="manual") as emulator, emulator.client(timeout=0.3) as client:
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
        print(f"servo {UNPLUGGED} plugged back in")
        silent = 0  # ms of simulated time since power-on
        controller.check_servos()
        while controller.lost:
            check(silent < COMEBACK_TIMEOUT_MS, "servo 2 never came back")
            control.clock_step(ms=ROUND_MS)
            silent += ROUND_MS
            controller.check_servos()
        print(f"controller: servo {UNPLUGGED} answers again after {silent} ms")
        check(silent >= BOOT_MS, f"servo 2 answered {silent} ms after power-on, before its boot "
                                 f"time ({BOOT_MS} ms)")
        check(silent < BOOT_MS + ROUND_MS, f"servo 2 answered only {silent} ms after power-on, "
                                           f"not at the first round after its boot time")
        check(controller.reconfigured == [UNPLUGGED], "the controller should have re-applied "
              f"servo 2's settings, got {controller.reconfigured}")
        check(client.read(UNPLUGGED, TORQUE_ENABLE, 1).value == 1, "servo 2's torque should be on")
        wait_for_position(control, client, UNPLUGGED, GOALS[UNPLUGGED])
        for servo in SERVOS:
            wait_for_position(control, client, servo, GOALS[servo])
        check(emulator.stop() == 0, "dxlemu should stop cleanly")


if __name__ == "__main__":
    run_example(main, "ok: the unplugged servo was noticed, came back after boot, and was configured again")
