"""The clients `exec_test.py` runs with and without `dxlemu exec`: each does what a real
controller library does to its port and prints what happened as one JSON line on stdout.

  flood PATH COUNT tcflush|ioctl   COUNT Sync Writes, each after an output flush as pyserial's
                                   flushOutput() does (termios.tcflush, or ioctl(TCFLSH)), then
                                   a Ping of ID 1 whose reply shows that every byte was read;
                                   a first line {"written": BYTES} once everything is written,
                                   before it waits for the reply
  serial PATH                      DynamixelSDK's and pyserial's low-latency open (TIOCGSERIAL,
                                   ASYNC_LOW_LATENCY, TIOCSSERIAL, read back), modem lines, RS-485
  foreign                          the same requests, and output flushes (and none, to compare),
                                   on a pseudo-terminal of its own, which is no dxlemu port
"""
import array
import errno
import fcntl
import json
import os
import select
import struct
import sys
import termios
import time
import tty

from dxl_client import Port, packet2

ASYNC_LOW_LATENCY = 1 << 13
TIOCGRS485 = 0x542E
TIOCSRS485 = 0x542F
SER_RS485_ENABLED = 1
SER_RS485_RTS_ON_SEND = 2
SYNC_WRITE = 0x83
PING = 0x01
LED = 65  # XM430-W350's LED, a RAM item: writing it changes nothing lasting
SERIAL_INTS = 32  # pyserial's buffer for struct serial_struct
RS485_BYTES = 32  # struct serial_rs485
# Reading back what a PTY of the client's own holds: all of it within READ_ALL_S when nothing
# was flushed, else until QUIET_S pass without a byte.
READ_ALL_S = 10.0
QUIET_S = 0.2


def flood(path: str, count: int, mode: str) -> dict:
    port = Port(path)
    written = 0
    for i in range(count):
        if mode == "tcflush":
            termios.tcflush(port.fd, termios.TCOFLUSH)
        else:
            fcntl.ioctl(port.fd, termios.TCFLSH, termios.TCOFLUSH)
        params = struct.pack("<HH", LED, 1) + bytes([1, i & 1, 2, i & 1, 3, i & 1])
        packet = packet2(0xFE, SYNC_WRITE, params)
        port.write(packet)
        written += len(packet)
    ping = packet2(1, PING)
    port.write(ping)
    # The test may hold the daemon stopped until everything is written: it waits for this line.
    print(json.dumps({"written": written + len(ping)}), flush=True)
    status = port.status2(timeout=10)
    port.close()
    return {"sent": count, "ping_answered": status is not None}


def attempt(call) -> dict:
    """{"ok": result} or {"errno": name} of one ioctl."""
    try:
        return {"ok": call()}
    except OSError as e:
        return {"errno": errno.errorcode.get(e.errno, str(e.errno))}


def serial_requests(fd: int) -> dict:
    def low_latency():
        buf = array.array("i", [0] * SERIAL_INTS)
        fcntl.ioctl(fd, termios.TIOCGSERIAL, buf)
        before = list(buf[:8])
        buf[4] |= ASYNC_LOW_LATENCY
        fcntl.ioctl(fd, termios.TIOCSSERIAL, buf)
        after = array.array("i", [0] * SERIAL_INTS)
        fcntl.ioctl(fd, termios.TIOCGSERIAL, after)
        # type, line, port, irq, flags, xmit_fifo_size, custom_divisor, baud_base
        return {"before": before, "flags_after": after[4]}

    def modem():
        def get():
            return struct.unpack("i", fcntl.ioctl(fd, termios.TIOCMGET, struct.pack("i", 0)))[0]
        states = [get()]
        fcntl.ioctl(fd, termios.TIOCMBIC, struct.pack("i", termios.TIOCM_RTS))
        states.append(get())
        fcntl.ioctl(fd, termios.TIOCMBIS, struct.pack("i", termios.TIOCM_RTS))
        states.append(get())
        fcntl.ioctl(fd, termios.TIOCMSET, struct.pack("i", 0))
        states.append(get())
        return states

    def rs485():
        wanted = struct.pack("IIII", SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND, 0, 0, 0)
        wanted += bytes(RS485_BYTES - len(wanted))
        before = fcntl.ioctl(fd, TIOCGRS485, bytes(RS485_BYTES))
        fcntl.ioctl(fd, TIOCSRS485, wanted)
        after = fcntl.ioctl(fd, TIOCGRS485, bytes(RS485_BYTES))
        return {"flags_before": struct.unpack_from("I", before)[0],
                "flags_after": struct.unpack_from("I", after)[0]}

    return {"low_latency": attempt(low_latency), "modem": attempt(modem), "rs485": attempt(rs485)}


def serial(path: str) -> dict:
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
    try:
        return serial_requests(fd)
    finally:
        os.close(fd)


def flushed_bytes(master: int, slave: int, flush, everything: bool) -> dict:
    """Bytes written to `slave` with nobody reading `master`, then `flush`ed: a PTY holds 4 KiB
    in the master's line discipline and the rest in its buffer, which an output flush discards,
    so more than 4 KiB written and fewer read back shows a flush that discards. The kernel's
    worker moves the rest to the master as the reads make room: they go on until `everything`
    written has come (at most READ_ALL_S), or else until QUIET_S pass without a byte."""
    os.set_blocking(slave, False)
    written = 0
    try:
        while written < 12000:
            written += os.write(slave, b"U" * 1000)
    except BlockingIOError:
        pass
    flush(slave)
    read = 0
    deadline = time.monotonic() + READ_ALL_S
    while not (everything and read == written):
        wait = deadline - time.monotonic() if everything else QUIET_S
        if wait <= 0 or not select.select([master], [], [], wait)[0]:
            break
        read += len(os.read(master, 65536))
    return {"written": written, "read": read}


def foreign() -> dict:
    out = {}
    for name, flush in (("none", lambda fd: None),
                        ("tcflush", lambda fd: termios.tcflush(fd, termios.TCOFLUSH)),
                        ("ioctl", lambda fd: fcntl.ioctl(fd, termios.TCFLSH, termios.TCOFLUSH))):
        master, slave = os.openpty()
        tty.setraw(slave)
        out[name] = flushed_bytes(master, slave, flush, everything=name == "none")
        os.close(master)
        os.close(slave)
    master, slave = os.openpty()
    out.update(serial_requests(slave))
    os.close(master)
    os.close(slave)
    return out


def main() -> None:
    what = sys.argv[1]
    if what == "flood":
        result = flood(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    elif what == "serial":
        result = serial(sys.argv[2])
    elif what == "foreign":
        result = foreign()
    else:
        raise SystemExit(f"unknown client {what!r}")
    print(json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
