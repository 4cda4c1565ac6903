"""A small DYNAMIXEL client over a serial port, standard library only, for the end-to-end tests.

It builds instruction packets (Protocol 1.0 and 2.0, with byte stuffing), reads status packets
with a timeout, and starts and stops the dxlemu daemon. The codec is written independently of
the C++ one, from ../shared/reference/protocol1.md, protocol2.md and protocol2-crc.md.
"""
import json
import os
import select
import signal
import socket
import subprocess
import termios
import time

BAUD = {57600: termios.B57600, 115200: termios.B115200, 1000000: termios.B1000000}


def crc16(data: bytes) -> int:
    """CRC-16 of Protocol 2.0: polynomial 0x8005, initial 0, MSB first (protocol2-crc.md)."""
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def stuff(region: bytes) -> bytes:
    """Inserts 0xFD after every FF FF FD (protocol2.md "Packet Process")."""
    out = bytearray()
    for b in region:
        out.append(b)
        if len(out) >= 3 and out[-3:] == b"\xff\xff\xfd":
            out.append(0xFD)
    return bytes(out)


def packet2(ident: int, instruction: int, params: bytes = b"") -> bytes:
    """A Protocol 2.0 instruction packet."""
    body = stuff(bytes([instruction]) + params)
    length = len(body) + 2
    head = bytes([0xFF, 0xFF, 0xFD, 0x00, ident, length & 0xFF, length >> 8]) + body
    crc = crc16(head)
    return head + bytes([crc & 0xFF, crc >> 8])


def packet1(ident: int, instruction: int, params: bytes = b"") -> bytes:
    """A Protocol 1.0 instruction packet."""
    body = bytes([ident, len(params) + 2, instruction]) + params
    return b"\xff\xff" + body + bytes([~sum(body) & 0xFF])


class Port:
    """The client side of the emulated serial port, raw, at a chosen baud rate."""

    def __init__(self, path: str, baud: int = 57600):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        self.set_baud(baud)

    def set_baud(self, baud: int) -> None:
        attr = termios.tcgetattr(self.fd)
        attr[0] = attr[1] = attr[3] = 0  # raw: no input, output or local processing
        attr[2] = termios.CS8 | termios.CREAD | termios.CLOCAL
        attr[4] = attr[5] = BAUD[baud]
        termios.tcsetattr(self.fd, termios.TCSANOW, attr)
        termios.tcflush(self.fd, termios.TCIOFLUSH)

    def write(self, data: bytes) -> None:
        os.write(self.fd, data)

    def read(self, count: int, timeout: float = 1.0) -> bytes:
        """Up to `count` bytes, waiting at most `timeout` seconds in all."""
        end = time.monotonic() + timeout
        data = b""
        while len(data) < count:
            left = end - time.monotonic()
            if left <= 0 or not select.select([self.fd], [], [], left)[0]:
                break
            data += os.read(self.fd, count - len(data))
        return data

    def status2(self, timeout: float = 1.0):
        """One Protocol 2.0 status packet as (id, error, params), or None on timeout."""
        head = self.read(7, timeout)
        if len(head) < 7:
            return None
        length = head[5] | (head[6] << 8)
        rest = self.read(length, timeout)
        packet = head + rest
        if len(rest) < length or crc16(packet[:-2]) != (packet[-2] | (packet[-1] << 8)):
            raise AssertionError("bad status packet: " + packet.hex(" "))
        return packet[4], packet[8], packet[9:-2]

    def status1(self, timeout: float = 1.0):
        """One Protocol 1.0 status packet as (id, error, params), or None on timeout."""
        head = self.read(4, timeout)
        if len(head) < 4:
            return None
        rest = self.read(head[3], timeout)
        packet = head + rest
        if ~sum(packet[2:-1]) & 0xFF != packet[-1]:
            raise AssertionError("bad status packet: " + packet.hex(" "))
        return packet[2], packet[4], packet[5:-1]

    def close(self) -> None:
        os.close(self.fd)


class Daemon:
    """`dxlemu run ARGS` in the background, ready once its readiness line has been read."""

    def __init__(self, *args: str):
        binary = os.environ.get("DXLEMU_BIN", "build/emulator/dxlemu")
        self.proc = subprocess.Popen([binary, "run", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        if not line:
            raise AssertionError("dxlemu exited: " + self.proc.stderr.read())
        self.ready = json.loads(line)

    def stop(self) -> int:
        """SIGTERM, then the exit code."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout=5)
        finally:
            self.proc.stdout.close()
            self.proc.stderr.close()


class Control:
    """A client of the control API: newline-delimited JSON over the daemon's Unix socket."""

    def __init__(self, path: str, timeout: float = 5.0):
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.sock.settimeout(timeout)
        self.sock.connect(path)
        self.buffer = b""
        self.next_id = 1

    def send_line(self, line: bytes) -> None:
        self.sock.sendall(line + b"\n")

    def reply(self) -> dict:
        while b"\n" not in self.buffer:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise AssertionError("the control socket closed")
            self.buffer += chunk
        line, self.buffer = self.buffer.split(b"\n", 1)
        return json.loads(line)

    def request(self, cmd: str, **args) -> dict:
        """Sends {"id": n, "cmd": cmd, ...args} and returns the whole reply."""
        request_id = self.next_id
        self.next_id += 1
        self.send_line(json.dumps({"id": request_id, "cmd": cmd, **args}).encode())
        reply = self.reply()
        assert reply.get("id") == request_id, reply
        return reply

    def call(self, cmd: str, **args):
        """The result of a request that must succeed."""
        reply = self.request(cmd, **args)
        if not reply.get("ok"):
            raise AssertionError(f"{cmd} failed: {reply.get('error')}")
        return reply["result"]

    def close(self) -> None:
        self.sock.close()
