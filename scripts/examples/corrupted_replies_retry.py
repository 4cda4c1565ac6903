#!/usr/bin/env python3
"""Fault injection example: 5 % of the servos' replies arrive with a bad CRC; the controller
must retry, and every read must eventually succeed.

    python3 scripts/examples/corrupted_replies_retry.py    # exit 0: every step held

Copy it and replace `Controller` with your own controller code. It needs only the standard
library and the dxlemu package (python/ of the dxlemu checkout: adjust the sys.path line below,
or set PYTHONPATH). The binary is $DXLEMU_BIN, else `dxlemu` on PATH, else the checkout's build.

The steps:
1. dxlemu runs the default bus (three XM430-W350, IDs 1 ~ 3) with a fixed `--seed`, so the
   same replies are corrupted on every run, under `--timing manual`: replies go out at once
   and none is dropped as late, however busy the machine, so every retry is the rule's doing.
2. The script adds a rule with the control API:
   fault.add {"action": "corrupt_crc", "match": {"port": "dxl0"}, "probability": 0.05}.
3. The controller reads Present Position 500 times, retrying a read whose reply has a bad
   CRC or does not come.
4. Every read succeeded; some needed retries; the rule's counters (fault.list) and the bus's
   (stats: faults_injected) show exactly as many corrupted replies as the controller retried
   for.
"""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))  # the dxlemu package

from dxlemu import BadPacket, Client, CommTimeout, Emulator, Reply  # noqa: E402
from dxlemu.example import Failure, check, run_example  # noqa: E402

PRESENT_POSITION = 132  # XM430-W350 (e-Manual; models/xm430-w350.json)
SERVOS = (1, 2, 3)
READS = 500
SEED = 20240607
PROBABILITY = 0.05
ATTEMPTS = 5  # per read: at 5 % corruption, four retries failing in a row is a 1-in-3-million event


class Controller:
    """The controller under test, reduced to what matters here: reads with retries, counting
    why it retried."""

    def __init__(self, client: Client, attempts: int):
        self.client = client
        self.attempts = attempts
        self.bad_crc = 0
        self.timeouts = 0

    def read(self, servo: int, address: int, length: int) -> Reply:
        """A Read retried on a bad CRC or a timeout, up to `attempts` times in all."""
        for _ in range(self.attempts):
            try:
                return self.client.read(servo, address, length)
            except BadPacket:
                self.bad_crc += 1
            except CommTimeout:
                self.timeouts += 1
        raise Failure(f"servo {servo}: no valid reply in {self.attempts} attempts")

    @property
    def retries(self) -> int:
        """Reads sent again."""
        return self.bad_crc + self.timeouts


def main() -> None:
    with Emulator(timing="manual", seed=SEED) as emulator, emulator.client(timeout=1.0) as client:
        control = emulator.control
        rule = control.fault_add({"action": "corrupt_crc", "match": {"port": "dxl0"},
                                  "probability": PROBABILITY})
        controller = Controller(client, ATTEMPTS)
        for index in range(READS):
            servo = SERVOS[index % len(SERVOS)]
            reply = controller.read(servo, PRESENT_POSITION, 4)
            check(reply == (bytes([0x00, 0x08, 0x00, 0x00]), 0),
                  f"servo {servo}: Present Position should be 2048, got {reply}")
        print(f"controller: {READS} reads, {controller.retries} retries "
              f"({controller.bad_crc} bad CRC, {controller.timeouts} timeouts)")
        check(controller.bad_crc > 0, "some replies should have been corrupted")
        check(controller.timeouts == 0, "a corrupted reply still arrives: no timeouts expected")
        check(controller.retries < READS * PROBABILITY * 3,
              f"far more retries than 5 % of {READS} reads: {controller.retries}")

        (counters,) = [entry for entry in control.fault_list() if entry["id"] == rule]
        print(f"fault.list: rule {rule} matched {counters['matched']} replies, "
              f"fired {counters['fired']} times")
        check(counters["fired"] == controller.bad_crc,
              f"the rule fired {counters['fired']} times, the controller saw "
              f"{controller.bad_crc} bad CRCs")
        check(counters["matched"] == READS + controller.retries,
              f"every reply should have been matched: {counters['matched']} of "
              f"{READS + controller.retries}")
        stats = control.stats("dxl0")["dxl0"]
        print(f"stats: {stats['frames']} instructions, {stats['replies']} replies, "
              f"{stats['faults_injected']} faults injected")
        check(stats["frames"] == READS + controller.retries,
              f"the bus should count {READS + controller.retries} instructions, got {stats}")
        check(stats["faults_injected"] == controller.bad_crc,
              f"the bus should count {controller.bad_crc} faults injected, got {stats}")
        control.fault_remove(rule)
        check(controller.read(1, PRESENT_POSITION, 4).error == 0, "reads work without the rule")
        check(emulator.stop() == 0, "dxlemu should stop cleanly")


if __name__ == "__main__":
    run_example(main, "ok: every read succeeded, retries matched the corrupted replies")
