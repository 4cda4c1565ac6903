#!/usr/bin/env python3
"""What the web interface costs the daemon: CPU and reply lateness with the page open, graphing
10 items at 10 ms with the packet view recording, against the same run without the page.

Each round starts `dxlemu run --servo xm430-w350:1-10 --baud 1000000 --web 0` three times: with
no page; with the page's requests (trace.subscribe, and sample.subscribe of 10 items every 10 ms)
made over its WebSocket by a small client that reads every message, which is the daemon's whole
side of the page; and with the page itself open in headless Chromium, graphing and recording
packets (the order rotates between rounds, so drift of the machine hits each alike). A DynamixelSDK client (tests/e2e/sdk_client.py: the SDK's
own wire behaviour over pyserial) runs Sync Reads of Present Position of the 10 servos back to
back for D seconds at 1 Mbit/s, as a control loop does. Measured per run:

  CPU      = the daemon's run time (/proc/PID/task/*/schedstat) over those D seconds / D, % of a CPU
  p50, p99 = the reply lateness the daemon measured (`stats`: lateness against the modelled time)
  reads    = Sync Read round trips the client completed (the load is the same in both runs)
  lost     = events the page lost as a slow client (its `dropped` count): 0 when it keeps up

The browser's own CPU is not the daemon's and is not counted; on a 2-core machine it competes
with the daemon and the client for the cores, which the third kind's lateness shows and the
second's does not.

    /usr/bin/python3 bench/web_cost.py --dxlemu build/emulator/dxlemu [--seconds 10] [--rounds 3]
                                       [--no-browser] [--isolate] [--daemon-arg ARG]...

--isolate puts the daemon alone on the last CPU and the client, the page's stand-in and Chromium
on the others: what the daemon itself spends, without the page competing for its core.

Markdown to stdout, progress to stderr.
"""
from __future__ import annotations

import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests" / "e2e"))
sys.path.insert(0, str(ROOT / "tests" / "web"))

from dxlemu.daemon import Emulator  # noqa: E402
import sdk_client as sdk  # noqa: E402
from websocket_client import WebSocket  # noqa: E402

PRESENT_POSITION = 132
SERVOS = list(range(1, 11))
GRAPH_ITEMS = [(1, "present_position"), (2, "present_position"), (3, "present_position"),
               (4, "present_position"), (5, "present_position"), (1, "present_velocity"),
               (2, "present_current"), (3, "present_temperature"), (4, "present_input_voltage"),
               (5, "moving")]


def cpu_seconds(pid: int) -> float:
    total = 0
    for path in glob.glob(f"/proc/{pid}/task/*/schedstat"):
        with open(path) as f:
            total += int(f.read().split()[0])
    return total / 1e9


def open_page(url: str):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,900"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    driver.get(url)
    driver.execute_script("""
        document.querySelector('#pkt-record') && (document.querySelector('#pkt-record').checked = true,
          document.querySelector('#pkt-record').dispatchEvent(new Event('change')));""")
    driver.find_element("css selector", '#view-tabs button[data-view="packets"]').click()
    driver.find_element("css selector", '#view-tabs button[data-view="graph"]').click()
    for servo, item in GRAPH_ITEMS:
        driver.execute_script("window.dxlemu.graphAdd('dxl0', arguments[0], arguments[1])",
                              servo, item)
    return driver


class PageRequests:
    """What the page asks of the daemon in those two views, over its WebSocket, from a process of
    its own that takes every message as a browser would: the daemon's side of the page without
    the browser's CPU, and without sharing the client's Python interpreter (its lock)."""

    def __init__(self, url: str):
        self.process = subprocess.Popen([sys.executable, __file__, "--page-requests", url],
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        if self.process.stdout.readline().strip() != "ready":
            raise RuntimeError("the page's stand-in did not start")
        self.lost = 0

    def close(self) -> None:
        self.process.stdin.close()  # the stand-in reports what it lost and ends
        self.lost = int(self.process.stdout.readline() or 0)
        self.process.wait(timeout=10)


def serve_page_requests(url: str) -> None:
    """The stand-in's process: subscribes as the page does, reads until stdin closes, then
    prints how many events the daemon dropped for it."""
    ws = WebSocket(url)
    ws.call({"id": 1, "cmd": "trace.subscribe"})
    items = [{"port": "dxl0", "servo": servo, "item": item} for servo, item in GRAPH_ITEMS]
    ws.call({"id": 2, "cmd": "sample.subscribe", "items": items, "period_ms": 10})
    lost = [0]

    def drain() -> None:
        while True:
            try:
                for line in ws.message().split("\n"):
                    if line.startswith('{"event":"dropped"'):
                        lost[0] = json.loads(line)["total"]
            except (OSError, ConnectionError):
                return

    threading.Thread(target=drain, daemon=True).start()
    print("ready", flush=True)
    sys.stdin.read()
    print(lost[0], flush=True)
    os._exit(0)


def pin_daemon(pid: int, cpu: int) -> None:
    """Every thread of the daemon on `cpu` alone (--isolate)."""
    for task in os.listdir(f"/proc/{pid}/task"):
        os.sched_setaffinity(int(task), {cpu})


def one_run(binary: str, seconds: float, client: str | None, isolate: bool,
            extra: list[str]) -> dict:
    with Emulator(binary=binary, servos=["xm430-w350:1-10"], baud=1000000,
                  args=["--web", "0", *extra]) as emulator:
        if isolate:
            pin_daemon(emulator.process.proc.pid, max(os.sched_getaffinity(emulator.process.proc.pid)))
        url = emulator.process.ready[0]["web"]
        driver = open_page(url) if client == "page" else None
        socket_client = PageRequests(url) if client == "socket" else None
        try:
            port = sdk.PortHandler(emulator.link)
            port.openPort()
            port.setBaudRate(1000000)
            handler = sdk.Protocol2PacketHandler()
            group = sdk.GroupSyncRead(port, handler, PRESENT_POSITION, 4)
            for servo in SERVOS:
                group.addParam(servo)
            time.sleep(1.0)  # the page settles: subscriptions made, first draws done
            pid = emulator.process.proc.pid
            start_cpu, start = cpu_seconds(pid), time.monotonic()
            reads = 0
            while time.monotonic() - start < seconds:
                if group.txRxPacket() == sdk.COMM_SUCCESS:
                    reads += 1
            elapsed = time.monotonic() - start
            cpu = (cpu_seconds(pid) - start_cpu) / elapsed * 100
            lateness = emulator.control.call("stats", port="dxl0")["dxl0"]["lateness"]
            lost = (driver.execute_script("return window.dxlemu.droppedEvents()") if driver
                    else socket_client.lost if socket_client else 0)
            port.closePort()
        finally:
            if driver:
                driver.quit()
            if socket_client:
                socket_client.close()
    return {"cpu": cpu, "p50": lateness["p50_us"], "p99": lateness["p99_us"],
            "max": lateness["max_us"], "reads": reads, "lost": lost}


CLIENTS = {None: "no page", "socket": "page's requests", "page": "page in Chromium"}


def main() -> int:
    if len(sys.argv) == 3 and sys.argv[1] == "--page-requests":
        serve_page_requests(sys.argv[2])
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dxlemu", required=True)
    parser.add_argument("--seconds", type=float, default=10)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--no-browser", action="store_true",
                        help="only the page's requests over a WebSocket, no Chromium")
    parser.add_argument("--isolate", action="store_true",
                        help="the daemon alone on the last CPU, everything else (the client, "
                             "the page, Chromium) on the others: the daemon's own cost, "
                             "without competing for a core")
    parser.add_argument("--daemon-arg", action="append", default=[],
                        help="one more argument of every `dxlemu run` (repeatable), e.g. "
                             "--daemon-arg=--realtime-priority --daemon-arg=10")
    args = parser.parse_args()
    if args.isolate:
        cpus = sorted(os.sched_getaffinity(0))
        if len(cpus) < 2:
            parser.error("--isolate needs at least 2 CPUs")
        os.sched_setaffinity(0, set(cpus[:-1]))  # inherited by Chromium and the daemon
    clients = [None, "socket"] + ([] if args.no_browser else ["page"])
    runs: dict = {client: [] for client in clients}
    for round_index in range(args.rounds):
        # Rotated each round, so that drift of the machine hits every kind alike.
        order = clients[round_index % len(clients):] + clients[:round_index % len(clients)]
        for client in order:
            print(f"round {round_index + 1}: {CLIENTS[client]}", file=sys.stderr)
            runs[client].append(one_run(args.dxlemu, args.seconds, client, args.isolate,
                                        args.daemon_arg))
    print(f"### {args.rounds} rounds of {args.seconds:g} s, 10 XM430-W350 at 1 Mbit/s, "
          "Sync Read back to back" + (", the daemon alone on a CPU" if args.isolate else "")
          + (", dxlemu run " + " ".join(args.daemon_arg) if args.daemon_arg else "") + "\n")
    print("| run | daemon CPU % | lateness p50 µs | p99 µs | max µs | Sync Reads | events lost |")
    print("|---|---|---|---|---|---|---|")
    for client in clients:
        for index, run in enumerate(runs[client]):
            print(f"| {CLIENTS[client]} {index + 1} | {run['cpu']:.1f} | {run['p50']:.0f} | "
                  f"{run['p99']:.0f} | {run['max']:.0f} | {run['reads']} | {run['lost']} |")
    print()
    base = {k: statistics.median(r[k] for r in runs[None]) for k in ("cpu", "p99")}
    for client in clients[1:]:
        median = {k: statistics.median(r[k] for r in runs[client]) for k in ("cpu", "p99")}
        print(f"- {CLIENTS[client]} against no page (medians): CPU {median['cpu']:.1f} % vs "
              f"{base['cpu']:.1f} % ({median['cpu'] - base['cpu']:+.1f} points of a core), "
              f"lateness p99 {median['p99']:.0f} µs vs {base['p99']:.0f} µs "
              f"({median['p99'] - base['p99']:+.0f} µs).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
