"""End-to-end: `dxlemu clone` against a dxlemu bus standing in for the hardware
(docs/robots.md "Cloning a real bus").

A bus with servos at two rates and both DYNAMIXEL protocols, with EEPROM settings away from the
factory values, is cloned; the config written is served, and every item of every servo read over
the wire from the clone equals the same read from the original. The original's trace shows that
the scan sent only Ping and Read. A FEETECH bus is cloned the same way.
"""
import json
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

from dxl_client import Daemon, dxlemu_command, timeout_scale
from dxlemu.protocol import Client

MODELS = Path(__file__).resolve().parents[2] / "models"
# Items that change on their own: a clock, and nothing else at rest.
VOLATILE = {"realtime_tick"}
# The scan's wait for each ID's reply (--timeout-ms). Under manual timing a servo answers as soon
# as the daemon reads the Ping: the wait covers only a loaded machine's scheduling, and every
# absent ID costs all of it.
SCAN_TIMEOUT_MS = 100


def model_items(name: str) -> list[dict]:
    base = name.split("@")[0]
    for path in (MODELS / f"{base}.json", MODELS / "feetech" / f"{base}.json"):
        if path.exists():
            return json.loads(path.read_text(encoding="utf-8"))["items"]
    raise AssertionError(f"no model file for {name}")


class CloneTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def path(self, name: str) -> str:
        return os.path.join(self.dir.name, name)

    def serve(self, config: dict, name: str, *extra: str) -> str:
        """Serves `config` (its one port linked at a fresh path); returns the link."""
        link = self.path(name)
        config["ports"][0]["link"] = link
        file = self.path(name + ".json")
        with open(file, "w", encoding="utf-8") as f:
            json.dump(config, f)
        # Manual timing: replies go out at once and are never dropped as late; the scan's own
        # per-ID timeout (SCAN_TIMEOUT_MS) stays on the wall clock, as against hardware.
        daemon = Daemon("--config", file, "--timing", "manual", *extra)
        self.addCleanup(daemon.stop)
        return link

    def clone(self, link: str, *options: str) -> dict:
        out = self.path("cloned.json")
        timeout_ms = str(round(SCAN_TIMEOUT_MS * timeout_scale()))
        proc = subprocess.run(dxlemu_command("clone", link, "--out", out, "--timeout-ms", timeout_ms,
                                             *options),
                              capture_output=True, text=True, timeout=120 * timeout_scale())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("written to " + out, proc.stderr)
        with open(out, encoding="utf-8") as f:
            return json.load(f)

    def table(self, link: str, servo: dict, baud: int, protocol) -> dict[str, bytes]:
        """Every item of `servo` read over the wire, by key."""
        client = Client(link, baud=baud, protocol=protocol, timeout=1.0 * timeout_scale())
        try:
            out = {}
            for item in model_items(servo["model"]):
                if item["key"] in VOLATILE:
                    continue
                reply = client.read(servo["id"], item["address"], item["size"])
                out[item["key"]] = reply.data
            return out
        finally:
            client.close()

    def assert_same_bus(self, original: str, cloned: str, servos: list[tuple[dict, int, object]]):
        for servo, baud, protocol in servos:
            with self.subTest(servo=servo["id"]):
                self.assertEqual(self.table(cloned, servo, baud, protocol),
                                 self.table(original, servo, baud, protocol))

    def test_a_dynamixel_bus_is_cloned_item_for_item_without_a_write(self):
        xm = {"model": "xm430-w350", "ids": [1, 2],
              "items": {"return_delay_time": 0, "drive_mode": 1, "homing_offset": -300,
                        "min_position_limit": 1000, "max_position_limit": 3000,
                        "velocity_limit": 200}}
        ax = {"model": "ax-12a", "id": 7, "baud": 1000000,
              "items": {"cw_angle_limit": 100, "return_delay_time": 10}}
        xl = {"model": "xl330-m288@52", "id": 9, "items": {"secondary_id": 20}}
        trace = self.path("trace.jsonl")
        original = self.serve({"ports": [{"name": "arm", "servos": [xm, ax, xl]}]}, "original",
                              "--trace", trace)
        config = self.clone(original, "--baud", "1000000", "--baud", "57600", "--ids", "0-12",
                            "--name", "arm")
        servos = config["ports"][0]["servos"]
        self.assertEqual([(s["model"], s["id"]) for s in servos],
                         [("ax-12a", 7), ("xm430-w350", 1), ("xm430-w350", 2),
                          ("xl330-m288@52", 9)])
        self.assertEqual(servos[1]["items"]["homing_offset"], -300)
        cloned = self.serve(config, "cloned")
        self.assert_same_bus(original, cloned, [
            ({"model": "ax-12a", "id": 7}, 1000000, 1),
            ({"model": "xm430-w350", "id": 1}, 57600, 2),
            ({"model": "xm430-w350", "id": 2}, 57600, 2),
            ({"model": "xl330-m288@52", "id": 9}, 57600, 2)])
        # The scan (and this test's reads) sent Ping and Read only: nothing was written.
        with open(trace, encoding="utf-8") as f:
            heard = [json.loads(line) for line in f]
        asked = {r["packet"].split()[1] for r in heard if r["dir"] == "in" and "packet" in r}
        self.assertEqual(asked, {"ping", "read"})

    def test_a_feetech_bus_is_cloned_by_its_model_numbers(self):
        sts = {"model": "sts3215", "ids": [1, 2, 3],
               "items": {"position_offset": -120, "minimum_angle_limit": 600,
                         "maximum_angle_limit": 3400, "return_delay_time": 5}}
        scs = {"model": "scs0009", "id": 8, "items": {"maximum_angle_limit": 900}}
        original = self.serve({"ports": [{"name": "so101", "servos": [sts, scs]}]}, "original")
        config = self.clone(original, "--baud", "1000000", "--ids", "0-10")
        servos = config["ports"][0]["servos"]
        self.assertEqual([(s["model"], s["id"]) for s in servos],
                         [("sts3215", 1), ("sts3215", 2), ("sts3215", 3), ("scs0009", 8)])
        self.assertIn("FEETECH", servos[0]["description"])
        cloned = self.serve(config, "cloned")
        self.assert_same_bus(original, cloned, [
            ({"model": "sts3215", "id": i}, 1000000, "feetech") for i in (1, 2, 3)] + [
            ({"model": "scs0009", "id": 8}, 1000000, "feetech")])

    def test_modbus_servos_are_found_only_when_asked_and_cloned_by_their_registers(self):
        ph = {"model": "ph42-020-s300-r", "ids": [3, 9], "protocol": "modbus",
              "items": {"homing_offset": -300, "velocity_limit": 1000}}
        trace = self.path("trace.jsonl")
        original = self.serve({"ports": [{"name": "hand", "servos": [ph]}]}, "original",
                              "--trace", trace)
        config = self.clone(original, "--protocol", "modbus", "--baud", "57600", "--ids", "0-10")
        servos = config["ports"][0]["servos"]
        self.assertEqual([(s["model"], s["id"]) for s in servos],
                         [("ph42-020-s300-r", 3), ("ph42-020-s300-r", 9)])
        self.assertIn("Modbus RTU", servos[0]["description"])
        for servo in servos:
            self.assertEqual(servo["items"]["protocol_type"], 10)
            self.assertEqual(servo["items"]["homing_offset"], -300)
            self.assertEqual(servo["items"]["velocity_limit"], 1000)
        # Only Read Holding Registers crossed the line.
        with open(trace, encoding="utf-8") as f:
            heard = [json.loads(line) for line in f]
        asked = {r["packet"].split()[1] for r in heard if r["dir"] == "in" and "packet" in r}
        self.assertEqual(asked, {"read_holding_registers"})
        # The cloned config is served as it was.
        self.serve(config, "cloned")

    def test_a_bus_where_nothing_answers_is_an_error_and_writes_nothing(self):
        original = self.serve({"ports": [{"name": "empty", "servos": []}]}, "original")
        out = self.path("cloned.json")
        proc = subprocess.run(dxlemu_command("clone", original, "--out", out, "--baud", "57600",
                                             "--ids", "0-3", "--timeout-ms", "5"),
                              capture_output=True, text=True, timeout=60 * timeout_scale())
        self.assertEqual(proc.returncode, 1)
        self.assertIn("no servo of a known model answered on " + original, proc.stderr)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
