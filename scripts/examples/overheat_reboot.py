#!/usr/bin/env python3
"""Fault injection example: a servo overheats mid-motion; the controller must notice the alert
bit, read Hardware Error Status, and recover the servo with Reboot once it has cooled down.

    python3 scripts/examples/overheat_reboot.py        # exit 0: every step held

Copy it and replace `Controller` with your own controller code. It needs only the standard
library and the dxlemu package (python/ of the dxlemu checkout: adjust the sys.path line below,
or set PYTHONPATH). The binary is $DXLEMU_BIN, else `dxlemu` on PATH, else the checkout's build.

The steps:
1. dxlemu runs the default bus (three XM430-W350, IDs 1 ~ 3, Protocol 2.0) under
   `--timing manual`: simulated time (the move, the servo's tick that detects the error, the
   boot time) passes only when the script steps it, as the controller's `sleep`, so what the
   controller sees does not depend on how busy the machine is, and replies are never dropped
   as late.
2. The controller turns torque on and sends servo 3 on a slow move, then polls every servo.
3. While servo 3 moves, the script makes it overheat with the control API:
   fault.add {"action": "hardware_error", "kind": "overheating", "match": {"servos": [3]}}.
4. The controller sees the alert bit (0x80) in servo 3's status, reads Hardware Error Status
   (Overheating, 0x04): the servo shut down (Torque Enable 0, writing 1 refused) and stops
   short of its goal.
5. The script removes the rule (the servo has cooled down); the error stays latched.
6. The controller reboots servo 3, waits for it to boot, and finds no alert and Torque Enable
   writable again.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))  # the dxlemu package

from dxlemu import Client, CommError, Emulator  # noqa: E402
from dxlemu.example import check, run_example  # noqa: E402

# XM430-W350 control table (e-Manual; models/xm430-w350.json).
TORQUE_ENABLE, HARDWARE_ERROR_STATUS, PROFILE_VELOCITY = 64, 70, 112
GOAL_POSITION, MOVING, PRESENT_POSITION = 116, 122, 132
OVERHEATING = 0x04  # Hardware Error Status bit
RESULT_FAIL = 0x01  # Protocol 2.0 error code
ALERT = 0x80

SERVOS = (1, 2, 3)
HOT_SERVO = 3
SLOW = 20  # Profile Velocity, 0.229 rev/min units: about 300 pulses/s
BOOT_TIMEOUT_S = 3.0  # servos are silent for 0.4 s after Reboot
BOOT_RETRY_S = 0.1  # between the controller's pings of a rebooting servo
ALERT_TIMEOUT_S = 5.0
STOP_TIMEOUT_S = 2.0
POLL_S = 0.01  # between the controller's polls


class Controller:
    """The controller under test, reduced to what matters here: it polls its servos, watches
    the alert bit, diagnoses and reboots a servo that reports a hardware error."""

    def __init__(self, client: Client, sleep: Callable[[float], None]):
        self.client = client
        # How the controller lets time pass between tries: time.sleep against hardware, the
        # emulator's clock.step here.
        self.sleep = sleep
        self.alerts: dict[int, int] = {}  # servo -> Hardware Error Status seen with its alert

    def start(self, servo: int, goal: int) -> None:
        """Torque on and a slow move to `goal`."""
        for address, value, size in ((PROFILE_VELOCITY, SLOW, 4), (TORQUE_ENABLE, 1, 1),
                                     (GOAL_POSITION, goal, 4)):
            reply = self.client.write_int(servo, address, value, size)
            check(reply.error == 0,
                  f"servo {servo}: write of {address} refused: 0x{reply.error:02x}")

    def poll(self) -> dict[int, int]:
        """Reads every servo's Present Position; a servo whose status carries the alert bit gets
        its Hardware Error Status read and recorded. Returns the positions."""
        positions = {}
        for servo, reply in self.client.sync_read(PRESENT_POSITION, 4, SERVOS).items():
            positions[servo] = reply.signed
            if reply.alert and servo not in self.alerts:
                self.alerts[servo] = self.client.read(servo, HARDWARE_ERROR_STATUS, 1).value
        return positions

    def recover(self, servo: int) -> None:
        """Reboot, then ping until the servo has booted."""
        reply = self.client.reboot(servo)
        check(reply.error & 0x7F == 0, f"servo {servo}: Reboot refused: 0x{reply.error:02x}")
        waited = 0.0
        while True:
            try:
                self.client.ping(servo)
                break
            except CommError:
                check(waited < BOOT_TIMEOUT_S, f"servo {servo} did not come back after Reboot")
                self.sleep(BOOT_RETRY_S)
                waited += BOOT_RETRY_S
        self.alerts.pop(servo, None)


def main() -> None:
    with Emulator(timing="manual") as emulator, emulator.client(timeout=0.5) as client:
        control = emulator.control

        def sleep(seconds: float) -> None:
            control.clock_step(ns=round(seconds * 1e9))

        controller = Controller(client, sleep)
        controller.start(HOT_SERVO, goal=3048)
        sleep(0.1)
        check(client.read(HOT_SERVO, MOVING, 1).value == 1, "servo 3 should be moving")

        rule = control.fault_add({"action": "hardware_error", "kind": "overheating",
                                  "match": {"port": "dxl0", "servos": [HOT_SERVO]}})
        print(f"fault rule {rule}: servo {HOT_SERVO} overheats mid-motion")
        waited = 0.0
        controller.poll()
        while HOT_SERVO not in controller.alerts:
            check(waited < ALERT_TIMEOUT_S, "the controller never saw the alert bit")
            sleep(POLL_S)
            waited += POLL_S
            controller.poll()
        print(f"controller: alert from servo {HOT_SERVO}, Hardware Error Status "
              f"0x{controller.alerts[HOT_SERVO]:02x}")
        check(controller.alerts == {HOT_SERVO: OVERHEATING},
              f"only servo 3 should report Overheating, got {controller.alerts}")
        check(client.read(HOT_SERVO, TORQUE_ENABLE, 1) == (b"\x00", ALERT),
              "the overheated servo should have shut down (Torque Enable 0, alert)")
        refused = client.write_int(HOT_SERVO, TORQUE_ENABLE, 1, 1)
        check(refused.error == ALERT | RESULT_FAIL,
              f"Torque Enable should be refused before Reboot, got error 0x{refused.error:02x}")
        waited = 0.0
        while client.read(HOT_SERVO, MOVING, 1).value != 0:  # no torque: it coasts to a stop
            check(waited < STOP_TIMEOUT_S, "the shut-down servo should have stopped")
            sleep(POLL_S)
            waited += POLL_S
        print(f"servo {HOT_SERVO} shut down and stopped at "
              f"{client.read(HOT_SERVO, PRESENT_POSITION, 4).signed} of 3048")

        control.fault_remove(rule)
        print("fault rule removed: the servo has cooled down")
        check(client.ping(HOT_SERVO).alert, "the error should stay latched until Reboot")

        controller.recover(HOT_SERVO)
        print(f"controller: servo {HOT_SERVO} rebooted")
        status = client.read(HOT_SERVO, HARDWARE_ERROR_STATUS, 1)
        check(status == (b"\x00", 0), f"no error expected after Reboot, got {status}")
        check(client.write_int(HOT_SERVO, TORQUE_ENABLE, 1, 1) == (b"", 0),
              "Torque Enable should be writable again after Reboot")
        check(client.read(HOT_SERVO, TORQUE_ENABLE, 1).value == 1, "torque should be on")
        controller.poll()
        check(not controller.alerts, f"no alert expected after recovery, got {controller.alerts}")
        check(emulator.stop() == 0, "dxlemu should stop cleanly")


if __name__ == "__main__":
    run_example(main, "ok: overheating noticed by the alert bit, recovered with Reboot")
