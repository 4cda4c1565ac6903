#!/usr/bin/python3
"""The daemon with physics under a polling client: `dxlemu run --timing realtime` with the SO-101
follower profile (robots/so101-follower.json) and its physics file (robots/physics/
so101-follower.json) merged into one config, as a config carrying both would be (the "mjcf"
made absolute), and a client that reads Present Position (56, 2 bytes) of the six STS3215 one
after another at POLL_HZ cycles per second for SECONDS. The same again with the profile alone
(no physics), interleaved, ROUNDS times. Reported (median over rounds): the daemon's CPU share
(utime + stime of /proc/PID/stat over wall time, in % of one CPU) and the reads it answered.

Usage: bench/physics_daemon.py --dxlemu build/emulator/dxlemu [--seconds 10] [--poll-hz 100]
       [--rounds 3]
Python standard library only."""
import argparse
import json
import os
import select
import statistics
import subprocess
import sys
import tempfile
import termios
import time
from pathlib import Path

ROBOTS = Path(__file__).resolve().parents[1] / "robots"
PRESENT_POSITION = 56
READ = 0x02
IDS = range(1, 7)
REPLY_TIMEOUT_S = 0.1


def merged_config(directory: str, with_physics: bool) -> str:
    config = json.loads((ROBOTS / "so101-follower.json").read_text())
    config["ports"][0]["link"] = os.path.join(directory, "arm")
    if with_physics:
        physics = json.loads((ROBOTS / "physics" / "so101-follower.json").read_text())
        physics["mjcf"] = str(ROBOTS / "physics" / physics["mjcf"])
        config["physics"] = physics
    path = os.path.join(directory, "config.json")
    with open(path, "w") as f:
        json.dump(config, f)
    return path


def feetech_read(servo: int, address: int, size: int) -> bytes:
    body = bytes([servo, 4, READ, address, size])
    return b"\xff\xff" + body + bytes([~sum(body) & 0xFF])


def open_port(path: str) -> int:
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
    attrs = termios.tcgetattr(fd)
    attrs[0] = 0                                            # iflag: raw
    attrs[1] = 0                                            # oflag
    attrs[2] = termios.CS8 | termios.CREAD | termios.CLOCAL  # cflag: 8N1
    attrs[3] = 0                                            # lflag: no echo, no canonical mode
    attrs[4] = attrs[5] = termios.B1000000                  # the profile's 1 Mbit/s
    termios.tcsetattr(fd, termios.TCSANOW, attrs)
    return fd


def read_reply(fd: int, length: int) -> bool:
    data = b""
    deadline = time.monotonic() + REPLY_TIMEOUT_S
    while len(data) < length:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            return False
        data += os.read(fd, length - len(data))
    return True


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def run(dxlemu: str, with_physics: bool, seconds: float, poll_hz: float) -> tuple[float, int]:
    with tempfile.TemporaryDirectory() as directory:
        config = merged_config(directory, with_physics)
        daemon = subprocess.Popen([dxlemu, "run", "--config", config, "--timing", "realtime"],
                                  stdout=subprocess.PIPE, text=True)
        try:
            ready = json.loads(daemon.stdout.readline())
            fd = open_port(ready["pty"])
            answered = 0
            reply_length = 6 + 2  # header, ID, length, error, 2 data bytes, checksum
            start_wall, start_cpu = time.monotonic(), cpu_seconds(daemon.pid)
            next_cycle = start_wall
            while time.monotonic() - start_wall < seconds:
                for servo in IDS:
                    os.write(fd, feetech_read(servo, PRESENT_POSITION, 2))
                    answered += read_reply(fd, reply_length)
                next_cycle += 1 / poll_hz
                time.sleep(max(0.0, next_cycle - time.monotonic()))
            wall = time.monotonic() - start_wall
            share = (cpu_seconds(daemon.pid) - start_cpu) / wall
            os.close(fd)
            return share, answered
        finally:
            daemon.terminate()
            daemon.wait()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dxlemu", required=True)
    parser.add_argument("--seconds", type=float, default=10)
    parser.add_argument("--poll-hz", type=float, default=100)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    shares = {True: [], False: []}
    reads = {True: [], False: []}
    for round_ in range(args.rounds):
        for with_physics in (True, False):
            share, answered = run(args.dxlemu, with_physics, args.seconds, args.poll_hz)
            shares[with_physics].append(share)
            reads[with_physics].append(answered)
            print(f"round {round_ + 1}, {'physics' if with_physics else 'no physics'}: "
                  f"CPU {share * 100:.1f} %, {answered} reads answered", file=sys.stderr)
    print(f"SO-101 follower daemon, --timing realtime, {args.seconds:g} s, six reads per cycle "
          f"at {args.poll_hz:g} Hz, median of {args.rounds} rounds\n")
    print("| variant | dxlemu CPU (% of one CPU) | reads answered |")
    print("|---|---|---|")
    for with_physics, name in ((True, "with MuJoCo"), (False, "without physics")):
        print(f"| {name} | {statistics.median(shares[with_physics]) * 100:.1f} | "
              f"{statistics.median(reads[with_physics]):.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
