"""Browser tests of the web interface (docs/web.md): the real daemon with `--web 0`, the page in
headless Chromium driven by Selenium (Debian: chromium, chromium-driver, python3-selenium), and
a DYNAMIXEL client on the PTY at the same time.

- The page loads with no console error and the bus view lists the servos.
- A value the client writes over the PTY shows in the bus view within a second.
- An item edited in the control table view is what the client then reads over the PTY; a
  refused edit shows the API's reason.
- A fault preset clicked in the page makes the client's next read go unanswered, as a dropped
  reply does.
- The graph's CSV holds the values the control API reports for the same items.
- The packet view lists the client's packets; its pcap download is a valid capture.
- The 3D view draws the robot (canvas not blank): needs MuJoCo ($DXLEMU_HAVE_MUJOCO=1).
- Without the token, with a wrong one, or from a foreign Origin, requests are refused (403);
  `--web-read-only` refuses every change, in the page and over its WebSocket.

    ctest --test-dir build/dev -R web -V
    DXLEMU_BIN=../../build/dev/emulator/dxlemu python3 -m unittest -v web_test   # in tests/web
"""
from __future__ import annotations

import base64
import http.client
import json
import os
import struct
import sys
import time
import unittest
import urllib.parse
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))

from dxlemu.daemon import Emulator  # noqa: E402
from dxlemu.protocol import Client  # noqa: E402
from websocket_client import WebSocket  # noqa: E402

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import WebDriverWait
except ImportError:  # a missing tool fails loudly: see WebTest.setUpClass
    webdriver = None

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
HAVE_MUJOCO = os.environ.get("DXLEMU_HAVE_MUJOCO") == "1"
# How long to wait for the page to show something: the browser and a daemon under the
# sanitizers share a 2-core machine. What is asserted is what shows, not how soon, except for
# the bus view's one second (test_pty_write_shows_in_the_bus_view_within_a_second).
WAIT = 20.0

LED = 65              # XM430-W350 control table
GOAL_POSITION = 116
RETURN_DELAY = 9


def browser() -> "webdriver.Chrome":
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,900",
                 "--use-gl=swiftshader", "--enable-unsafe-swiftshader"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def require_tools() -> None:
    missing = [what for what, ok in (("python3-selenium", webdriver is not None),
                                     (CHROMIUM + " (chromium)", os.path.exists(CHROMIUM)),
                                     (CHROMEDRIVER + " (chromium-driver)",
                                      os.path.exists(CHROMEDRIVER))) if not ok]
    if missing:
        raise RuntimeError("the browser tests need " + ", ".join(missing) +
                           ": scripts/setup.sh installs them")


def severe(driver) -> list[dict]:
    return [entry for entry in driver.get_log("browser") if entry["level"] == "SEVERE"]


def web_url(emulator: Emulator) -> str:
    return emulator.process.ready[0]["web"]


def wait_for(predicate, timeout: float = WAIT, what: str = "condition"):
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        try:
            last = predicate()
        except Exception as error:  # noqa: BLE001 - a stale element retried
            last = error
        if last and not isinstance(last, Exception):
            return last
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what} (last: {last!r})")


def edit_item(driver, key: str, value: str) -> None:
    """Clicks item `key`'s raw value in the control table view, types `value` and Enter. The view
    redraws the table as it polls: a click that meets a redrawn row is tried again."""
    def open_editor():
        driver.find_element(By.CSS_SELECTOR, f'#ct-table tr[data-key="{key}"] td.raw').click()
        return driver.find_element(By.CSS_SELECTOR, f'#ct-table tr[data-key="{key}"] input')
    field = wait_for(open_editor, what=f"an editor on {key}")
    field.send_keys(Keys.CONTROL, "a")
    field.send_keys(value, Keys.ENTER)


def upgrade(url: str, *, token: str | None, origin: str | None) -> int:
    """The HTTP status of a WebSocket upgrade of /ws with `token` and `origin`."""
    parts = urllib.parse.urlsplit(url)
    connection = http.client.HTTPConnection(parts.hostname, parts.port, timeout=10)
    headers = {"Upgrade": "websocket", "Connection": "Upgrade", "Sec-WebSocket-Version": "13",
               "Sec-WebSocket-Key": base64.b64encode(os.urandom(16)).decode()}
    if origin is not None:
        headers["Origin"] = origin
    path = "/ws" + ("?token=" + token if token is not None else "")
    connection.request("GET", path, headers=headers)
    status = connection.getresponse().status
    connection.close()
    return status


class WebTest(unittest.TestCase):
    """One daemon (three XM430-W350, realtime) with its page open in one browser."""

    @classmethod
    def setUpClass(cls):
        require_tools()
        cls.emulator = Emulator(servos=["xm430-w350:1-3"], args=["--web", "0"])
        cls.url = web_url(cls.emulator)
        cls.driver = browser()
        cls.driver.get(cls.url)
        cls.client = Client(cls.emulator.link, baud=57600)

    @classmethod
    def tearDownClass(cls):
        cls.driver.quit()
        cls.emulator.stop()

    def setUp(self):
        self.emulator.control.call("fault.clear")
        self.driver.get_log("browser")  # what earlier tests left

    def tearDown(self):
        self.assertEqual(severe(self.driver), [])

    def view(self, name: str) -> None:
        self.driver.find_element(By.CSS_SELECTOR, f'#view-tabs button[data-view="{name}"]').click()

    def cell(self, servo: int, key: str) -> str:
        return self.driver.find_element(
            By.CSS_SELECTOR, f'#bus-table tr[data-servo="{servo}"] td[data-key="{key}"]').text

    def test_bus_view_lists_the_servos(self):
        self.view("bus")
        rows = wait_for(lambda: self.driver.find_elements(By.CSS_SELECTOR, "#bus-table tr[data-servo]")
                        if len(self.driver.find_elements(By.CSS_SELECTOR,
                                                         "#bus-table tr[data-servo]")) == 3 else None,
                        what="three servo rows")
        self.assertEqual([row.get_attribute("data-servo") for row in rows], ["1", "2", "3"])
        self.assertIn("xm430-w350", rows[0].text.lower())

    def test_pty_write_shows_in_the_bus_view_within_a_second(self):
        self.view("bus")
        wait_for(lambda: self.cell(2, "torque"), what="the bus view")
        reply = self.client.write_int(2, 64, 1, 1)  # Torque Enable
        self.assertEqual(reply.error, 0)
        start = time.monotonic()
        wait_for(lambda: self.cell(2, "torque").strip().lower() in ("on", "true", "1", "yes"),
                 what="torque on in the bus view")
        self.assertLess(time.monotonic() - start, 1.0)
        self.client.write_int(2, 64, 0, 1)

    def test_an_item_edited_in_the_page_is_what_the_client_reads(self):
        self.view("table")
        select = wait_for(lambda: self.driver.find_element(By.ID, "servo-select"))
        self.driver.execute_script(
            "arguments[0].value = 'dxl0/3'; arguments[0].dispatchEvent(new Event('change'))", select)
        wait_for(lambda: self.driver.find_element(
            By.CSS_SELECTOR, '#ct-table tr[data-key="return_delay_time"] td.raw').text == "250",
            what="servo 3's table")
        edit_item(self.driver, "return_delay_time", "17")
        wait_for(lambda: self.client.read(3, RETURN_DELAY, 1).data == bytes([17]),
                 what="the client reading 17")
        # A value out of range is refused with the API's reason, shown in the page.
        edit_item(self.driver, "return_delay_time", "99999")
        message = wait_for(lambda: self.driver.find_element(By.ID, "ct-message").text,
                           what="the refusal")
        self.assertIn("does not fit", message)
        self.assertEqual(self.client.read(3, RETURN_DELAY, 1).data, bytes([17]))
        self.emulator.control.call("set", port="dxl0", servo=3, item="return_delay_time", value=250)

    def test_a_fault_clicked_in_the_page_makes_the_next_read_fail(self):
        self.view("faults")
        select = wait_for(lambda: self.driver.find_element(By.ID, "fault-servo"))
        wait_for(lambda: "dxl0/1" in [o.get_attribute("value") for o in
                                     select.find_elements(By.TAG_NAME, "option")],
                 what="servo 1 in the fault target list")
        self.driver.execute_script(
            "arguments[0].value = 'dxl0/1'; arguments[0].dispatchEvent(new Event('change'))", select)
        self.assertIsNotNone(self.client.read(1, GOAL_POSITION, 4))
        self.driver.find_element(By.CSS_SELECTOR, 'button[data-preset="drop_replies"]').click()
        wait_for(lambda: self.emulator.control.call("fault.list"), what="the rule")
        self.client.send(1, 0x02, struct.pack("<HH", GOAL_POSITION, 4))
        with self.assertRaises(Exception):
            self.client.receive(1, timeout=0.5)
        self.assertGreater(self.emulator.control.call("fault.list")[0]["fired"], 0)
        wait_for(lambda: self.driver.find_elements(By.CSS_SELECTOR, "#fault-list tr[data-rule]"),
                 what="the rule listed in the page")

    def test_the_graph_csv_holds_what_the_api_reports(self):
        self.view("graph")
        control = self.emulator.control
        control.call("set", port="dxl0", servo=1, item="led", value=1)
        ready = self.driver.execute_async_script("""
            const done = arguments[arguments.length - 1];
            window.dxlemu.graphAdd('dxl0', 1, 'led');
            window.dxlemu.graphAdd('dxl0', 2, 'present_temperature');
            done(true);""")
        self.assertTrue(ready)
        wait_for(lambda: len(self.driver.execute_script(
            "return window.dxlemu.graphCsv()").strip().split("\n")) > 5, what="samples")
        control.call("set", port="dxl0", servo=1, item="led", value=0)
        control.call("set", port="dxl0", servo=2, item="present_temperature", value=44)
        time.sleep(0.3)  # lets the graph take samples after the change (10 ms period)
        csv = self.driver.execute_script("return window.dxlemu.graphCsv()").strip().split("\n")
        self.assertEqual(csv[0], "t_s,dxl0/1/led,dxl0/2/present_temperature")
        rows = [[float(x) for x in line.split(",")] for line in csv[1:]]
        times = [row[0] for row in rows]
        self.assertEqual(times, sorted(times))
        self.assertEqual(rows[0][1], 1)
        self.assertEqual(rows[-1][1:], [control.get(1, "led"), control.get(2, "present_temperature")])
        self.assertEqual(rows[-1][1:], [0, 44])
        control.call("set", port="dxl0", servo=2, item="present_temperature", value=25)

    def test_the_packet_view_lists_the_clients_packets(self):
        self.view("packets")
        time.sleep(0.2)  # the view's trace.subscribe goes out first
        self.client.ping(2)
        wait_for(lambda: any("ping" in row.text for row in self.driver.find_elements(
            By.CSS_SELECTOR, "#packets-table tbody tr")), what="the ping listed")
        pcap = self.driver.execute_script(
            "return Array.from(window.dxlemu.packetsPcap())")
        self.assertEqual(bytes(pcap[:4]), bytes.fromhex("d4c3b2a1"))
        self.assertEqual(struct.unpack("<I", bytes(pcap[20:24]))[0], 147)
        jsonl = self.driver.execute_script("return window.dxlemu.packetsJsonl()")
        records = [json.loads(line) for line in jsonl.strip().split("\n")]
        self.assertTrue(any(r.get("packet") == "id=2 ping" for r in records))


@unittest.skipUnless(HAVE_MUJOCO, "needs a build with MuJoCo (DXLEMU_HAVE_MUJOCO=1)")
class PhysicsViewTest(unittest.TestCase):
    def test_the_3d_view_draws_the_robot(self):
        require_tools()
        with Emulator(config=None, servos=None,
                      args=["--robot", "so101-follower", "--physics", "so101-follower",
                            "--web", "0", "--timing", "fast"]) as emulator:
            driver = browser()
            try:
                driver.get(web_url(emulator))
                driver.find_element(By.CSS_SELECTOR, '#view-tabs button[data-view="physics"]').click()
                canvas = wait_for(lambda: driver.find_element(By.ID, "physics-canvas"))
                time.sleep(1.0)
                png = canvas.screenshot_as_png
                colours = set(png[i] for i in range(100, len(png), 97))
                self.assertGreater(len(colours), 8, "the canvas is blank")
                self.assertEqual(severe(driver), [])
            finally:
                driver.quit()


class SecurityTest(unittest.TestCase):
    """What a request without the token, or from another page, gets (no browser needed)."""

    @classmethod
    def setUpClass(cls):
        cls.emulator = Emulator(servos=["xm430-w350:1"], args=["--web", "0", "--web-read-only"])
        cls.url = web_url(cls.emulator)
        parts = urllib.parse.urlsplit(cls.url)
        cls.host, cls.port = parts.hostname, parts.port
        cls.token = urllib.parse.parse_qs(parts.query)["token"][0]

    @classmethod
    def tearDownClass(cls):
        cls.emulator.stop()

    def get(self, path: str, headers: dict | None = None) -> http.client.HTTPResponse:
        connection = http.client.HTTPConnection(self.host, self.port, timeout=10)
        connection.request("GET", path, headers=headers or {})
        response = connection.getresponse()
        response.read()
        connection.close()
        return response

    def test_the_url_is_loopback_with_a_long_random_token(self):
        self.assertEqual(self.host, "127.0.0.1")
        self.assertRegex(self.token, r"^[0-9a-f]{32}$")

    def test_no_token_or_a_wrong_token_is_refused(self):
        self.assertEqual(self.get("/").status, 403)
        self.assertEqual(self.get("/?token=" + "0" * 32).status, 403)
        self.assertEqual(self.get("/app.js").status, 403)
        self.assertEqual(self.get("/?token=" + self.token).status, 200)

    def test_the_cookie_the_page_gets_serves_its_assets(self):
        response = self.get("/?token=" + self.token)
        cookie = response.getheader("Set-Cookie").split(";")[0]
        self.assertIn("SameSite=Strict", response.getheader("Set-Cookie"))
        self.assertEqual(self.get("/style.css", {"Cookie": cookie}).status, 200)
        self.assertEqual(self.get("/lib/three/build/three.min.js", {"Cookie": cookie}).status, 200)

    def test_a_websocket_from_another_origin_or_without_the_token_is_refused(self):
        own = f"http://{self.host}:{self.port}"
        self.assertEqual(upgrade(self.url, token=self.token, origin=own), 101)
        self.assertEqual(upgrade(self.url, token=self.token, origin="http://evil.example"), 403)
        self.assertEqual(upgrade(self.url, token=self.token, origin=None), 403)
        self.assertEqual(upgrade(self.url, token=None, origin=own), 403)
        self.assertEqual(upgrade(self.url, token="f" * 32, origin=own), 403)

    def test_read_only_refuses_every_change_and_still_shows(self):
        ws = WebSocket(self.url)
        try:
            listing = ws.call({"id": 1, "cmd": "list"})
            self.assertTrue(listing["ok"])
            refused = ws.call({"id": 2, "cmd": "set", "servo": 1, "item": "led", "value": 1})
            self.assertFalse(refused["ok"])
            self.assertIn("read-only", refused["error"])
            self.assertFalse(ws.call({"id": 3, "cmd": "fault.add",
                                      "rule": {"action": "drop_reply"}})["ok"])
            self.assertEqual(self.emulator.control.get(1, "led"), 0)
            self.assertTrue(ws.call({"id": 4, "cmd": "stats"})["ok"])
        finally:
            ws.close()

    def test_read_only_in_the_page_shows_the_refusal(self):
        require_tools()
        driver = browser()
        try:
            driver.get(self.url)
            driver.find_element(By.CSS_SELECTOR, '#view-tabs button[data-view="table"]').click()
            edit_item(driver, "led", "1")
            message = wait_for(lambda: driver.find_element(By.ID, "ct-message").text)
            self.assertIn("read-only", message)
            self.assertEqual(self.emulator.control.get(1, "led"), 0)
        finally:
            driver.quit()


if __name__ == "__main__":
    unittest.main()
