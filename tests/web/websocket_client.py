"""A minimal WebSocket client of the daemon's web interface (RFC 6455: text frames, masked), to
drive the control API as the page does without a browser: the browser tests' refusals and the
web benchmark's stand-in for the page (bench/web_cost.py). Standard library only."""
from __future__ import annotations

import base64
import json
import os
import socket
import struct
import urllib.parse


class WebSocket:
    """A minimal client of the page's WebSocket (RFC 6455, text frames, masked), to drive the API
    as the page does without a browser."""

    def __init__(self, url: str):
        parts = urllib.parse.urlsplit(url)
        token = urllib.parse.parse_qs(parts.query)["token"][0]
        self.sock = socket.create_connection((parts.hostname, parts.port), timeout=10)
        key = base64.b64encode(os.urandom(16)).decode()
        host = f"{parts.hostname}:{parts.port}"
        self.sock.sendall((f"GET /ws?token={token} HTTP/1.1\r\nHost: {host}\r\n"
                           f"Upgrade: websocket\r\nConnection: Upgrade\r\n"
                           f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n"
                           f"Origin: http://{host}\r\n\r\n").encode())
        response = b""
        while b"\r\n\r\n" not in response:
            response += self.sock.recv(4096)
        head, self.buffer = response.split(b"\r\n\r\n", 1)
        if not head.startswith(b"HTTP/1.1 101"):
            raise AssertionError(head.decode(errors="replace"))
        self.lines: list[dict] = []

    def send(self, text: str) -> None:
        payload = text.encode()
        mask = os.urandom(4)
        header = bytes([0x81])
        if len(payload) < 126:
            header += bytes([0x80 | len(payload)])
        else:
            header += bytes([0x80 | 126]) + struct.pack(">H", len(payload))
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def _exact(self, n: int) -> bytes:
        while len(self.buffer) < n:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("closed")
            self.buffer += chunk
        out, self.buffer = self.buffer[:n], self.buffer[n:]
        return out

    def message(self) -> str:
        first, second = self._exact(2)
        length = second & 0x7F
        if length == 126:
            length = struct.unpack(">H", self._exact(2))[0]
        elif length == 127:
            length = struct.unpack(">Q", self._exact(8))[0]
        payload = self._exact(length)
        if first & 0x0F == 8:
            raise ConnectionError("closed by the server: " + repr(payload))
        return payload.decode()

    def call(self, request: dict) -> dict:
        self.send(json.dumps(request))
        while True:
            for line in self.message().split("\n"):
                reply = json.loads(line)
                if reply.get("id") == request.get("id") and "event" not in reply:
                    return reply

    def close(self) -> None:
        self.sock.close()
