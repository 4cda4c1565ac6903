#!/usr/bin/env python3
"""Screenshots of the web page, one per view, for docs/web.md.

Starts `dxlemu run --robot ROBOT --physics ROBOT --web PORT --timing fast`, drives its bus with a
small client (so the Packets view has traffic), opens the page in headless Chromium at 1280x800,
exercises each view briefly (a hand sweep moves the graph and the arm, a fault turns a row red)
and saves docs/images/web-<view>.png. Fails (exit 1) when the browser's console shows an error.

Needs Debian's chromium, chromium-driver and python3-selenium:
    python3 scripts/web_screenshots.py build/dev/emulator/dxlemu
    python3 scripts/web_screenshots.py --url 'http://127.0.0.1:8080/?token=...' --link /tmp/dxlemu-so101-follower
      (the second form uses a daemon already running)
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

from selenium import webdriver
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
    """A controller polling the SO-101's six STS3215 (FEETECH): a Sync Read of Present Position
    and a Read of Present Temperature, 50 times a second, so there are packets to show."""

    def __init__(self, link, baud):
        super().__init__(daemon=True)
        self.link = link
        self.baud = baud
        self.stop = threading.Event()

    def run(self):
        fd = os.open(self.link, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        # The daemon hears the PTY at the baud the client sets, as a servo would.
        attributes = termios.tcgetattr(fd)
        attributes[4] = attributes[5] = getattr(termios, f"B{self.baud}")
        termios.tcsetattr(fd, termios.TCSANOW, attributes)
        termios.tcflush(fd, termios.TCIOFLUSH)
        sync_read = feetech_packet(0xFE, 0x82, [56, 2, 1, 2, 3, 4, 5, 6])
        n = 0
        while not self.stop.is_set():
            os.write(fd, sync_read)
            if n % 5 == 0:
                os.write(fd, feetech_packet(1 + n // 5 % 6, 0x02, [63, 1]))
            n += 1
            deadline = time.time() + 0.02
            while (left := deadline - time.time()) > 0:
                ready, _, _ = select.select([fd], [], [], left)
                if ready:
                    os.read(fd, 4096)
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
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dxlemu", nargs="?", help="the dxlemu binary (not with --url)")
    parser.add_argument("--url", help="the page of a daemon already running (with its ?token=)")
    parser.add_argument("--link", help="the bus's PTY link (with --url; default: the one started)")
    parser.add_argument("--robot", default="so101-follower")
    parser.add_argument("--port", type=int, default=8087, help="the --web port of the daemon started")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "images"))
    args = parser.parse_args()
    if not args.url and not args.dxlemu:
        parser.error("give the dxlemu binary, or --url of a running daemon")

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

        bus = api({"cmd": "list"})["ports"][0]
        port = bus["name"]
        client = BusClient(link, bus["servos"][0]["baud"])
        client.start()
        # Something to see: a hand sweeps every joint of the arm together.
        api({"cmd": "hand.sweep", "port": port, "order": "together", "speed_deg_s": 60})

        show("graph")
        for servo in (1, 2, 3):
            Select(driver.find_element(By.ID, "graph-servo")).select_by_value(f"{port}/{servo}")
            time.sleep(0.3)
            Select(driver.find_element(By.ID, "graph-item")).select_by_value("present_position")
            driver.find_element(By.ID, "graph-add").click()
            time.sleep(0.2)
        time.sleep(4)
        save("graph")

        show("faults")
        Select(driver.find_element(By.ID, "fault-servo")).select_by_value(f"{port}/3")
        driver.find_element(By.CSS_SELECTOR, 'button[data-preset="overheat"]').click()
        time.sleep(0.3)
        Select(driver.find_element(By.ID, "fault-servo")).select_by_value(f"{port}/5")
        driver.find_element(By.CSS_SELECTOR, 'button[data-preset="drop_replies"]').click()
        time.sleep(0.3)
        driver.find_element(By.ID, "scenario-load").click()
        time.sleep(1.5)
        save("faults")

        show("bus")
        time.sleep(1)
        save("bus")

        show("table")
        Select(driver.find_element(By.ID, "servo-select")).select_by_value(f"{port}/2")
        time.sleep(1)
        save("table")

        show("packets")
        time.sleep(2)
        save("packets")

        show("clock")
        time.sleep(1)
        save("clock")

        api({"cmd": "hand.sweep", "port": port, "order": "together", "speed_deg_s": 60})
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
