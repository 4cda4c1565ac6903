"""The controller's end of a serial line (the emulator's pseudo-terminal): raw termios at a
chosen baud rate, reads with a deadline, status packets framed out of the byte stream."""
from __future__ import annotations

import os
import select
import termios
import time
from typing import Callable

from .codec import BadPacket, Status, frame_status1, frame_status2

_STANDARD_RATES = (9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600,
                   1000000, 1152000, 1500000, 2000000, 2500000, 3000000, 3500000, 4000000)
BAUD_RATES: dict[int, int] = {rate: getattr(termios, f"B{rate}") for rate in _STANDARD_RATES
                              if hasattr(termios, f"B{rate}")}
"""Baud rates (bit/s) this port can be set to, with their termios constants."""

_READ_CHUNK = 4096

Framer = Callable[[bytes], "tuple[Status | None, int]"]


class Port:
    """A serial port opened raw (no echo, no line discipline, 8N1) at `baud` bit/s.

    Bytes read beyond the packet asked for are kept for the next read, so several replies
    (a broadcast Ping, a Sync Read) can be taken one at a time. Usable as a context manager."""

    def __init__(self, path: str, baud: int = 57600):
        self.path = path
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        self._pending = bytearray()
        try:
            self.set_baud(baud)
        except BaseException:
            os.close(self.fd)
            raise

    def set_baud(self, baud: int) -> None:
        """Sets the line raw at `baud` bit/s and discards whatever was waiting both ways."""
        if baud not in BAUD_RATES:
            raise ValueError(f"baud rate {baud} not offered by termios (offered: "
                             f"{', '.join(map(str, BAUD_RATES))})")
        attr = termios.tcgetattr(self.fd)
        attr[0] = attr[1] = attr[3] = 0  # raw: no input, output or local processing
        attr[2] = termios.CS8 | termios.CREAD | termios.CLOCAL
        attr[4] = attr[5] = BAUD_RATES[baud]
        termios.tcsetattr(self.fd, termios.TCSANOW, attr)
        self.flush_input()
        termios.tcflush(self.fd, termios.TCOFLUSH)

    def flush_input(self) -> None:
        """Discards every byte received and not yet read (a late or duplicated reply)."""
        termios.tcflush(self.fd, termios.TCIFLUSH)
        self._pending.clear()

    def write(self, data: bytes) -> None:
        """Writes all of `data`."""
        view = memoryview(data)
        while view:
            view = view[os.write(self.fd, view):]

    def _receive(self, deadline: float) -> bool:
        """Appends to the pending bytes what arrives before `deadline` (time.monotonic());
        False when nothing did."""
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([self.fd], [], [], left)[0]:
            return False
        self._pending += os.read(self.fd, _READ_CHUNK)
        return True

    def read(self, count: int, timeout: float = 1.0) -> bytes:
        """Up to `count` bytes, waiting at most `timeout` seconds in all."""
        deadline = time.monotonic() + timeout
        while len(self._pending) < count and self._receive(deadline):
            pass
        data = bytes(self._pending[:count])
        del self._pending[:count]
        return data

    def _status(self, framer: Framer, timeout: float) -> Status | None:
        deadline = time.monotonic() + timeout
        dropped = bytearray()
        while True:
            try:
                status, used = framer(bytes(self._pending))
            except BadPacket as error:
                del self._pending[:error.consumed]
                raise
            if status is not None:
                del self._pending[:used]
                return status
            dropped += self._pending[:used]
            del self._pending[:used]
            if not self._receive(deadline):
                if not self._pending and not dropped:
                    return None
                leftover = bytes(dropped + self._pending)
                self._pending.clear()
                raise BadPacket("no whole status packet before the timeout", leftover,
                                len(leftover))

    def status2(self, timeout: float = 1.0) -> Status | None:
        """The next Protocol 2.0 status packet, skipping garbage before it; None when nothing at
        all arrived within `timeout` seconds. Raises BadPacket for a bad CRC, or for bytes that
        did not make a whole packet in time."""
        return self._status(frame_status2, timeout)

    def status1(self, timeout: float = 1.0) -> Status | None:
        """The next Protocol 1.0 status packet, as `status2` does."""
        return self._status(frame_status1, timeout)

    def close(self) -> None:
        """Closes the port (idempotent)."""
        if self.fd >= 0:
            os.close(self.fd)
            self.fd = -1

    def __enter__(self) -> Port:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
