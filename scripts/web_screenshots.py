#!/usr/bin/env python3
"""Screenshots of the web page, one per view, for docs/web.md.

Starts `dxlemu run --robot ROBOT --physics ROBOT --web 0 --timing fast`, drives its bus with a
small FEETECH client (so the Packets view has traffic and the stats count EEPROM writes), opens
the page in headless Chromium at 1280x800, exercises each view (a hand sweep moves the graph and
the arm, a fault turns a row red, a scenario runs) and saves docs/images/web-<view>.png.
Exits 1 when the browser's console shows an error or a warning (other than SwiftShader's note on
reading the 3D canvas back, which the screenshot itself causes), or when a step fails.

Needs Debian's chromium, chromium-driver and python3-selenium (in /usr/bin/python3):
    python3 scripts/web_screenshots.py --dxlemu build/dev/emulator/dxlemu
    python3 scripts/web_screenshots.py --url 'http://127.0.0.1:8080/?token=...' --link /tmp/dxlemu-so101-follower
      (the second form uses a daemon already running, started with the same --robot and --physics)
"""
import argparse
import json
import os
import re
import select
import signal
import subprocess
import sys
import tempfile
import termios
import threading
import time
import tty

try:
    from selenium import webdriver
except ImportError:
    # Debian's python3-selenium is in the system's Python, which another python3 on the PATH
    # (pyenv, a virtualenv) does not see: run again there.
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
    sys.exit("web_screenshots.py needs python3-selenium, chromium and chromium-driver (scripts/setup.sh)")
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select, WebDriverWait

VIEWS = ["bus", "table", "graph", "packets", "faults", "clock", "physics"]


def start_daemon(binary, robot, port, link):
    """Starts the daemon; returns (process, page URL) once it says where the page is."""
    command = [binary, "run", "--robot", robot, "--physics", robot, "--link", link,
               "--web", f"127.0.0.1:{port}", "--timing", "fast"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    found = {}

    def watch(stream, name):
        for line in stream:
            if name == "stdout":
                try:
                    event = json.loads(line)
                    if isinstance(event, dict) and isinstance(event.get("web"), str):
                        found.setdefault("url", event["web"])
                except ValueError:
                    pass
            match = re.search(r"https?://\S+token=[0-9A-Za-z]+", line)
            if match:
                found.setdefault("url", match.group(0))
            found.setdefault("lines", []).append(line.rstrip())

    for stream, name in ((process.stdout, "stdout"), (process.stderr, "stderr")):
        threading.Thread(target=watch, args=(stream, name), daemon=True).start()
    deadline = time.time() + 30
    while "url" not in found:
        if process.poll() is not None or time.time() > deadline:
            process.kill()
            sys.exit("dxlemu did not print the page's URL:\n" + "\n".join(found.get("lines", [])))
        time.sleep(0.1)
    return process, found["url"]


def feetech_packet(servo_id, instruction, params):
    body = [servo_id, len(params) + 2, instruction, *params]
    return bytes([0xFF, 0xFF, *body, (~sum(body)) & 0xFF])


class BusClient(threading.Thread):
    """A controller on the SO-101's six STS3215 (FEETECH): first it sets servo 4's Return delay a
    few times (EEPROM unlocked, then locked again: the Clock & stats view counts the writes), then
    it polls: a Sync Read of Present position and a Read of Present temperature, 50 times a
    second, so there are packets to show."""

    LOCK_FLAG = 55
    RETURN_DELAY = 7

    def __init__(self, link, baud):
        super().__init__(daemon=True)
        self.link = link
        self.baud = baud
        self.stop = threading.Event()

    def exchange(self, fd, packet, expect, wait=0.05):
        """Sends `packet`, then reads until `expect` bytes came back or `wait` s passed."""
        os.write(fd, packet)
        deadline = time.time() + wait
        got = 0
        while got < expect and (left := deadline - time.time()) > 0:
            ready, _, _ = select.select([fd], [], [], left)
            if ready:
                got += len(os.read(fd, 4096))

    def run(self):
        fd = os.open(self.link, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        # The daemon hears the PTY at the baud the client sets, as a servo would.
        attributes = termios.tcgetattr(fd)
        attributes[4] = attributes[5] = getattr(termios, f"B{self.baud}")
        termios.tcsetattr(fd, termios.TCSANOW, attributes)
        termios.tcflush(fd, termios.TCIOFLUSH)
        status = 6  # bytes of a FEETECH status without parameters
        self.exchange(fd, feetech_packet(4, 0x03, [self.LOCK_FLAG, 0]), status)
        for delay in (0, 10, 20, 30, 0):
            self.exchange(fd, feetech_packet(4, 0x03, [self.RETURN_DELAY, delay]), status)
        self.exchange(fd, feetech_packet(4, 0x03, [self.LOCK_FLAG, 1]), status)
        sync_read = feetech_packet(0xFE, 0x82, [56, 2, 1, 2, 3, 4, 5, 6])
        n = 0
        while not self.stop.is_set():
            # One packet at a time, its replies read before the next: no collisions.
            self.exchange(fd, sync_read, 6 * (status + 2))
            if n % 5 == 0:
                self.exchange(fd, feetech_packet(1 + n // 5 % 6, 0x02, [63, 1]), status + 1)
            n += 1
            time.sleep(0.01)
        os.close(fd)


def make_driver():
    options = Options()
    options.binary_location = "/usr/bin/chromium"
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,800",
                     "--use-gl=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    # The page's own size, whatever the window's frame takes.
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                           {"width": 1280, "height": 800, "deviceScaleFactor": 1, "mobile": False})
    return driver


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[9:]))
    parser.add_argument("--dxlemu", help="the dxlemu binary to start, e.g. build/dev/emulator/dxlemu")
    parser.add_argument("binary", nargs="?", help=argparse.SUPPRESS)  # the older positional form
    parser.add_argument("--url", help="the page of a daemon already running (with its ?token=)")
    parser.add_argument("--link", help="the bus's PTY link (with --url; default: the one started)")
    parser.add_argument("--robot", default="so101-follower")
    parser.add_argument("--port", type=int, default=0, help="the --web port of the daemon started (0: a free one)")
    parser.add_argument("--out", default=os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "images")),
                        help="where the PNGs go (default: docs/images)")
    args = parser.parse_args()
    args.dxlemu = args.dxlemu or args.binary
    if bool(args.url) == bool(args.dxlemu):
        parser.error("give --dxlemu BINARY, or --url of a running daemon (and --link)")

    process = None
    link = args.link or os.path.join(tempfile.gettempdir(), f"dxlemu-screenshots-{os.getpid()}")
    if args.url:
        url = args.url
    else:
        process, url = start_daemon(args.dxlemu, args.robot, args.port, link)
    os.makedirs(args.out, exist_ok=True)
    client = None
    driver = make_driver()
    problems = []
    try:
        driver.get(url)
        WebDriverWait(driver, 15).until(lambda d: d.find_element(By.ID, "status").text == "connected")
        WebDriverWait(driver, 15).until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#bus-table tbody tr")) >= 6)

        def api(request):
            reply = driver.execute_async_script(
                "const done = arguments[arguments.length - 1];"
                "window.dxlemu.api(arguments[0]).then(done, (e) => done({ok: false, error: String(e)}));", request)
            if not reply.get("ok"):
                raise RuntimeError(f"{request}: {reply.get('error')}")
            return reply["result"]

        def show(view):
            driver.find_element(By.CSS_SELECTOR, f'#view-tabs button[data-view="{view}"]').click()
            time.sleep(0.3)

        def save(view):
            path = os.path.join(args.out, f"web-{view}.png")
            with open(path, "wb") as out:
                out.write(driver.get_screenshot_as_png())
            print(path)

        def choose(select_id, value):
            WebDriverWait(driver, 10).until(lambda d: value in [
                o.get_attribute("value") for o in d.find_elements(By.CSS_SELECTOR, f"#{select_id} option")])
            Select(driver.find_element(By.ID, select_id)).select_by_value(value)

        bus = api({"cmd": "list"})["ports"][0]
        port = bus["name"]
        client = BusClient(link, bus["servos"][0]["baud"])
        client.start()
        # Something to see: a hand sweeps every joint of the arm together, as a person would.
        api({"cmd": "hand.sweep", "port": port, "order": "together", "speed_deg_s": 60})

        # Faults: servo 3 overheats (its row turns red in the Bus view), servo 5's replies are
        # lost now and then, a scenario runs its steps.
        show("faults")
        choose("fault-servo", f"{port}/3")
        driver.find_element(By.CSS_SELECTOR, 'button[data-preset="overheat"]').click()
        time.sleep(0.3)
        choose("fault-servo", f"{port}/5")
        field = driver.find_element(By.ID, "fault-json")
        field.clear()
        field.send_keys(json.dumps({"action": "drop_reply", "match": {"port": port, "servos": [5]}, "probability": 0.2}))
        driver.find_element(By.ID, "fault-add").click()
        time.sleep(0.3)
        # A scenario still running when its screenshot is taken: a load on the shoulder now and
        # then, a minute long.
        scenario = {"steps": [{"at_ms": at, "cmd": "condition.set", "port": port, "servo": 2, "external_load": load}
                              for at, load in ((0, 0.2), (4000, 0), (20000, 0.3), (40000, 0), (60000, 0.1))]}
        text = '{"steps": [\n  ' + ",\n  ".join(json.dumps(step) for step in scenario["steps"]) + "\n]}"
        driver.execute_script("arguments[0].value = arguments[1]", driver.find_element(By.ID, "scenario-json"), text)
        driver.find_element(By.ID, "scenario-load").click()
        time.sleep(0.3)

        show("graph")
        for servo in (1, 2, 3, 6):
            choose("graph-servo", f"{port}/{servo}")
            choose("graph-item", "present_position")
            driver.find_element(By.ID, "graph-add").click()
            time.sleep(0.2)
        choose("graph-servo", f"{port}/2")
        choose("graph-item", "present_load")
        driver.find_element(By.ID, "graph-add").click()
        time.sleep(5)
        save("graph")

        show("bus")
        time.sleep(1)
        save("bus")

        show("table")
        choose("servo-select", f"{port}/2")
        time.sleep(1)
        save("table")

        show("packets")
        time.sleep(2)
        save("packets")

        show("faults")
        time.sleep(1)
        save("faults")

        show("clock")
        time.sleep(5)
        save("clock")

        api({"cmd": "hand.move", "port": port, "joint": 2, "position": 30, "duration_s": 1})
        api({"cmd": "hand.move", "port": port, "joint": 3, "position": -40, "duration_s": 1})
        show("physics")
        time.sleep(3)
        save("physics")

        for entry in driver.get_log("browser"):
            # Screenshots read the WebGL canvas back, which SwiftShader reports as a "GPU stall"
            # warning: that one is the screenshot's, not the page's.
            if entry["level"] == "SEVERE" or (entry["level"] == "WARNING" and "GL Driver Message" not in entry["message"]):
                problems.append(f'{entry["level"]}: {entry["message"]}')
    finally:
        driver.quit()
        if client:
            client.stop.set()
            client.join(5)
        if process:
            process.send_signal(signal.SIGTERM)
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                process.kill()
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
