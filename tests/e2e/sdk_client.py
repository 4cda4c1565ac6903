"""DynamixelSDK's Python package as it behaves on the wire and on the clock, over pyserial.

The real SDK cannot be installed here (it comes from PyPI); pyserial, the only thing it depends
on, is Debian's python3-serial. This module re-implements, without copying, what the SDK does
between a call such as `read4ByteTxRx` and the serial port, so that the end-to-end tests talk to
dxlemu exactly as an unmodified DynamixelSDK program would. Followed: ROBOTIS-GIT/DynamixelSDK,
Python package 4.0.2 (python/setup.py), Apache-2.0 (protocol2_packet_handler.py read from that
repository; port_handler.py, protocol1_packet_handler.py, group_sync_read.py and robotis_def.py
from copies of them in forks, the Linux C++ port_handler_linux.cpp for comparison):

- python/src/dynamixel_sdk/port_handler.py: pyserial opened as `serial.Serial(port, baudrate,
  bytesize=EIGHTBITS, timeout=0)` (non-blocking reads), `reset_input_buffer()` after opening;
  `setBaudRate` refuses rates outside the SDK's list and otherwise closes and reopens the port;
  `clearPort` is `ser.flush()` (drains output, discards no input); `tx_time_per_byte =
  1000 / baud * 10` ms; `setPacketTimeout(n) = tx_time_per_byte * n + LATENCY_TIMER * 2 + 2` ms
  with LATENCY_TIMER = 16; the clock is `time.time()` in ms.
- protocol2_packet_handler.py: CRC-16; byte stuffing, where `txPacket` calls `addStuffing` but
  keeps its result only when nothing was inserted, so an instruction that needs stuffing goes
  out unstuffed (kept: it is what the SDK puts on the wire); `rxPacket` reads
  `wait_length - rx_length` bytes at a time in a busy loop (no sleep, no `in_waiting`),
  resynchronises on FF FF FD (not followed by FD), drops a byte
  when RESERVED != 0, ID > 252, LENGTH > 1024 or INSTRUCTION != 0x55, and stops at the packet
  timeout; `txRxPacket` returns without reading for the broadcast ID, waits `len + 11` bytes'
  worth for Read and 11 otherwise, and skips status packets of other IDs; `broadcastPing` always
  waits its whole timeout `14 * 252 * tx_time_per_byte + 3 * 252 + 16` ms, then parses 14-byte
  packets; `syncReadTx` sets one timeout of `(11 + data_length) * n_ids` bytes for all replies.
- protocol1_packet_handler.py: checksum; `rxPacket` resynchronises on FF FF and drops a byte when
  ID > 0xFD, LENGTH > 250 or ERROR > 0x7F; `ping` is a Ping followed by a Read of Model Number
  (address 0, 2 bytes).
- group_sync_read.py: `addParam`, `txRxPacket` = `syncReadTx` then one `readRx` per ID in the
  order added, `isAvailable`, `getData`.
- robotis_def.py: IDs, instruction codes, COMM_* results, DXL_MAKEWORD and friends.

Simplified: only the calls the tests use (no Reg Write, Action, Reboot, Bulk, Fast Sync Read,
Sync Write); no Python 2 branch; CRC computed bitwise rather than from the SDK's table (same
polynomial 0x8005, same results); stuffing written as a function over bytes rather than the
SDK's in-place list edits (same output). Everything that decides what goes on the wire, how
long the SDK waits and which bytes it accepts is kept as the SDK has it.
"""
import time

import serial

from dxl_client import crc16  # the one CRC-16 of the tests; the SDK computes the same

LATENCY_TIMER = 16  # ms, port_handler.py
DEFAULT_BAUDRATE = 1000000
SDK_BAUDRATES = (9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600,
                 1000000, 1152000, 2000000, 2500000, 3000000, 3500000, 4000000)

BROADCAST_ID = 0xFE
MAX_ID = 0xFC
INST_PING, INST_READ, INST_WRITE, INST_ACTION = 1, 2, 3, 5
INST_STATUS, INST_SYNC_READ, INST_BULK_READ = 0x55, 0x82, 0x92

COMM_SUCCESS = 0
COMM_PORT_BUSY = -1000
COMM_TX_FAIL = -1001
COMM_RX_FAIL = -1002
COMM_TX_ERROR = -2000
COMM_RX_TIMEOUT = -3001
COMM_RX_CORRUPT = -3002
COMM_NOT_AVAILABLE = -9000


def DXL_MAKEWORD(a, b):
    return (a & 0xFF) | ((b & 0xFF) << 8)


def DXL_MAKEDWORD(a, b):
    return (a & 0xFFFF) | ((b & 0xFFFF) << 16)


def le_bytes(value, length):
    return [(value >> (8 * i)) & 0xFF for i in range(length)]


class PortHandler:
    """port_handler.py: one serial port, the packet timeout and the `is_using` flag."""

    def __init__(self, port_name):
        self.is_open = False
        self.baudrate = DEFAULT_BAUDRATE
        self.packet_start_time = 0.0
        self.packet_timeout = 0.0
        self.tx_time_per_byte = 0.0
        self.is_using = False
        self.port_name = port_name
        self.ser = None

    def openPort(self):
        return self.setBaudRate(self.baudrate)

    def closePort(self):
        self.ser.close()
        self.is_open = False

    def clearPort(self):
        self.ser.flush()

    def setBaudRate(self, baudrate):
        if baudrate not in SDK_BAUDRATES:
            return False  # the SDK's "TODO: setCustomBaudrate"
        self.baudrate = baudrate
        return self.setupPort()

    def getBaudRate(self):
        return self.baudrate

    def getBytesAvailable(self):
        return self.ser.in_waiting

    def readPort(self, length):
        return self.ser.read(length)

    def writePort(self, packet):
        return self.ser.write(packet)

    def setPacketTimeout(self, packet_length):
        self.packet_start_time = self.getCurrentTime()
        self.packet_timeout = (self.tx_time_per_byte * packet_length) + (LATENCY_TIMER * 2.0) + 2.0

    def setPacketTimeoutMillis(self, msec):
        self.packet_start_time = self.getCurrentTime()
        self.packet_timeout = msec

    def isPacketTimeout(self):
        if self.getTimeSinceStart() > self.packet_timeout:
            self.packet_timeout = 0
            return True
        return False

    def getCurrentTime(self):
        return round(time.time() * 1000000000) / 1000000.0  # ms

    def getTimeSinceStart(self):
        since = self.getCurrentTime() - self.packet_start_time
        if since < 0.0:
            self.packet_start_time = self.getCurrentTime()
        return since

    def setupPort(self):
        if self.is_open:
            self.closePort()
        self.ser = serial.Serial(port=self.port_name, baudrate=self.baudrate,
                                 bytesize=serial.EIGHTBITS, timeout=0)
        self.is_open = True
        self.ser.reset_input_buffer()
        self.tx_time_per_byte = (1000.0 / self.baudrate) * 10.0
        return True


# Protocol 2.0 packet offsets (protocol2_packet_handler.py)
P2_ID, P2_LENGTH_L, P2_LENGTH_H, P2_INSTRUCTION, P2_ERROR, P2_PARAMETER0 = 4, 5, 6, 7, 8, 8
TXPACKET_MAX_LEN = RXPACKET_MAX_LEN = 1024


class Protocol2PacketHandler:
    """protocol2_packet_handler.py, for the instructions the tests use."""

    def getProtocolVersion(self):
        return 2.0

    @staticmethod
    def addStuffing(packet):
        """FD after every FF FF FD from the instruction to the last parameter; LENGTH updated."""
        out = list(packet[:P2_INSTRUCTION])
        length = DXL_MAKEWORD(packet[P2_LENGTH_L], packet[P2_LENGTH_H])
        for b in packet[P2_INSTRUCTION:P2_INSTRUCTION + length - 2]:
            out.append(b)
            if b == 0xFD and out[-2] == 0xFF and out[-3] == 0xFF:
                out.append(0xFD)
        stuffed = len(out) - P2_INSTRUCTION + 2
        out[P2_LENGTH_L], out[P2_LENGTH_H] = stuffed & 0xFF, stuffed >> 8
        return out + [0, 0]  # CRC, filled in by txPacket

    @staticmethod
    def removeStuffing(packet):
        length = DXL_MAKEWORD(packet[P2_LENGTH_L], packet[P2_LENGTH_H])
        out = list(packet[:P2_INSTRUCTION])
        body = packet[P2_INSTRUCTION - 3:P2_INSTRUCTION + length - 2]
        for i in range(3, len(body)):
            if not (body[i] == 0xFD and body[i - 1] == 0xFD and body[i - 2] == 0xFF and
                    body[i - 3] == 0xFF):
                out.append(body[i])
        out += packet[P2_INSTRUCTION + length - 2:P2_INSTRUCTION + length]
        unstuffed = len(out) - P2_INSTRUCTION
        out[P2_LENGTH_L], out[P2_LENGTH_H] = unstuffed & 0xFF, unstuffed >> 8
        return out

    def txPacket(self, port, txpacket):
        if port.is_using:
            return COMM_PORT_BUSY, txpacket
        port.is_using = True
        # The SDK calls `self.addStuffing(txpacket)` and ignores the result: the list is changed
        # in place only when stuffing adds nothing, else a new list is made and dropped, so the
        # packet goes out unstuffed, its LENGTH and CRC those of the unstuffed bytes.
        stuffed = self.addStuffing(txpacket)
        if len(stuffed) == len(txpacket):
            txpacket = stuffed
        total = DXL_MAKEWORD(txpacket[P2_LENGTH_L], txpacket[P2_LENGTH_H]) + 7
        if total > TXPACKET_MAX_LEN:
            port.is_using = False
            return COMM_TX_ERROR, txpacket
        txpacket[0:4] = [0xFF, 0xFF, 0xFD, 0x00]
        crc = crc16(txpacket[:total - 2])
        txpacket[total - 2], txpacket[total - 1] = crc & 0xFF, crc >> 8
        port.clearPort()
        if port.writePort(txpacket) != total:
            port.is_using = False
            return COMM_TX_FAIL, txpacket
        return COMM_SUCCESS, txpacket

    def rxPacket(self, port):
        rxpacket = []
        result = COMM_TX_FAIL
        wait_length = 11  # FF FF FD 00 ID LEN_L LEN_H INST ERROR CRC_L CRC_H
        while True:
            rxpacket.extend(port.readPort(wait_length - len(rxpacket)))
            rx_length = len(rxpacket)
            if rx_length >= wait_length:
                idx = 0
                for idx in range(0, rx_length - 3):
                    if rxpacket[idx:idx + 3] == [0xFF, 0xFF, 0xFD] and rxpacket[idx + 3] != 0xFD:
                        break
                if idx == 0:
                    length = DXL_MAKEWORD(rxpacket[P2_LENGTH_L], rxpacket[P2_LENGTH_H])
                    if (rxpacket[3] != 0x00 or rxpacket[P2_ID] > MAX_ID or
                            length > RXPACKET_MAX_LEN or rxpacket[P2_INSTRUCTION] != INST_STATUS):
                        del rxpacket[0]
                        continue
                    if wait_length != length + P2_LENGTH_H + 1:
                        wait_length = length + P2_LENGTH_H + 1
                        continue
                    if rx_length < wait_length:
                        if port.isPacketTimeout():
                            result = COMM_RX_CORRUPT
                            break
                        continue
                    crc = DXL_MAKEWORD(rxpacket[wait_length - 2], rxpacket[wait_length - 1])
                    result = COMM_SUCCESS if crc16(rxpacket[:wait_length - 2]) == crc \
                        else COMM_RX_CORRUPT
                    break
                del rxpacket[0:idx]
            elif port.isPacketTimeout():
                result = COMM_RX_TIMEOUT if rx_length == 0 else COMM_RX_CORRUPT
                break
        port.is_using = False
        if result == COMM_SUCCESS:
            rxpacket = self.removeStuffing(rxpacket)
        return rxpacket, result

    def txRxPacket(self, port, txpacket):
        result, txpacket = self.txPacket(port, txpacket)
        if result != COMM_SUCCESS:
            return None, result, 0
        if txpacket[P2_INSTRUCTION] in (INST_BULK_READ, INST_SYNC_READ):
            result = COMM_NOT_AVAILABLE
        if txpacket[P2_ID] == BROADCAST_ID or txpacket[P2_INSTRUCTION] == INST_ACTION:
            port.is_using = False  # no status to wait for
            return None, result, 0
        if txpacket[P2_INSTRUCTION] == INST_READ:
            port.setPacketTimeout(DXL_MAKEWORD(txpacket[P2_PARAMETER0 + 2],
                                               txpacket[P2_PARAMETER0 + 3]) + 11)
        else:
            port.setPacketTimeout(11)
        while True:
            rxpacket, result = self.rxPacket(port)
            if result != COMM_SUCCESS or txpacket[P2_ID] == rxpacket[P2_ID]:
                break
        error = rxpacket[P2_ERROR] if result == COMM_SUCCESS else 0
        return rxpacket, result, error

    @staticmethod
    def instruction(dxl_id, inst, params=()):
        length = len(params) + 3
        return [0, 0, 0, 0, dxl_id, length & 0xFF, length >> 8, inst, *params, 0, 0]

    def ping(self, port, dxl_id):
        if dxl_id >= BROADCAST_ID:
            return 0, COMM_NOT_AVAILABLE, 0
        rxpacket, result, error = self.txRxPacket(port, self.instruction(dxl_id, INST_PING))
        model = DXL_MAKEWORD(rxpacket[P2_PARAMETER0 + 1], rxpacket[P2_PARAMETER0 + 2]) \
            if result == COMM_SUCCESS else 0
        return model, result, error

    def broadcastPing(self, port):
        status_length = 14
        wait_length = status_length * MAX_ID
        tx_time_per_byte = (1000.0 / port.getBaudRate()) * 10.0
        result, _ = self.txPacket(port, self.instruction(BROADCAST_ID, INST_PING))
        if result != COMM_SUCCESS:
            port.is_using = False
            return {}, result
        port.setPacketTimeoutMillis((wait_length * tx_time_per_byte) + (3.0 * MAX_ID) + 16.0)
        rxpacket = []
        while True:  # the SDK reads until the timeout, however early the last reply came
            rxpacket.extend(port.readPort(wait_length - len(rxpacket)))
            if port.isPacketTimeout():
                break
        port.is_using = False
        if not rxpacket:
            return {}, COMM_RX_TIMEOUT
        data_list = {}
        while True:
            if len(rxpacket) < status_length:
                return data_list, COMM_RX_CORRUPT
            idx = 0
            for idx in range(0, len(rxpacket) - 2):
                if rxpacket[idx:idx + 3] == [0xFF, 0xFF, 0xFD]:
                    break
            if idx != 0:
                del rxpacket[0:idx]
                continue
            crc = DXL_MAKEWORD(rxpacket[status_length - 2], rxpacket[status_length - 1])
            if crc16(rxpacket[:status_length - 2]) == crc:
                data_list[rxpacket[P2_ID]] = [
                    DXL_MAKEWORD(rxpacket[P2_PARAMETER0 + 1], rxpacket[P2_PARAMETER0 + 2]),
                    rxpacket[P2_PARAMETER0 + 3]]
                del rxpacket[0:status_length]
                if not rxpacket:
                    return data_list, COMM_SUCCESS
            else:
                del rxpacket[0:3]

    def readRx(self, port, dxl_id, length):
        while True:
            rxpacket, result = self.rxPacket(port)
            if result != COMM_SUCCESS or rxpacket[P2_ID] == dxl_id:
                break
        if result != COMM_SUCCESS:
            return [], result, 0
        data = rxpacket[P2_PARAMETER0 + 1:P2_PARAMETER0 + 1 + length]
        return data, (COMM_SUCCESS if len(data) == length else COMM_RX_CORRUPT), \
            rxpacket[P2_ERROR]

    def readTxRx(self, port, dxl_id, address, length):
        if dxl_id >= BROADCAST_ID:
            return [], COMM_NOT_AVAILABLE, 0
        txpacket = self.instruction(dxl_id, INST_READ, le_bytes(address, 2) + le_bytes(length, 2))
        rxpacket, result, error = self.txRxPacket(port, txpacket)
        if result != COMM_SUCCESS:
            return [], result, error
        data = rxpacket[P2_PARAMETER0 + 1:P2_PARAMETER0 + 1 + length]
        return data, (COMM_SUCCESS if len(data) == length else COMM_RX_CORRUPT), \
            rxpacket[P2_ERROR]

    def read1ByteTxRx(self, port, dxl_id, address):
        data, result, error = self.readTxRx(port, dxl_id, address, 1)
        return (data[0] if result == COMM_SUCCESS else 0), result, error

    def read2ByteTxRx(self, port, dxl_id, address):
        data, result, error = self.readTxRx(port, dxl_id, address, 2)
        return (DXL_MAKEWORD(*data) if result == COMM_SUCCESS else 0), result, error

    def read4ByteTxRx(self, port, dxl_id, address):
        data, result, error = self.readTxRx(port, dxl_id, address, 4)
        value = DXL_MAKEDWORD(DXL_MAKEWORD(data[0], data[1]), DXL_MAKEWORD(data[2], data[3])) \
            if result == COMM_SUCCESS else 0
        return value, result, error

    def writeTxRx(self, port, dxl_id, address, length, data):
        txpacket = self.instruction(dxl_id, INST_WRITE, le_bytes(address, 2) + list(data[:length]))
        _, result, error = self.txRxPacket(port, txpacket)
        return result, error

    def write1ByteTxRx(self, port, dxl_id, address, data):
        return self.writeTxRx(port, dxl_id, address, 1, [data])

    def write2ByteTxRx(self, port, dxl_id, address, data):
        return self.writeTxRx(port, dxl_id, address, 2, le_bytes(data, 2))

    def write4ByteTxRx(self, port, dxl_id, address, data):
        return self.writeTxRx(port, dxl_id, address, 4, le_bytes(data, 4))

    def syncReadTx(self, port, start_address, data_length, param, param_length):
        txpacket = self.instruction(BROADCAST_ID, INST_SYNC_READ,
                                    le_bytes(start_address, 2) + le_bytes(data_length, 2) +
                                    list(param[:param_length]))
        result, _ = self.txPacket(port, txpacket)
        if result == COMM_SUCCESS:
            port.setPacketTimeout((11 + data_length) * param_length)
        return result


class GroupSyncRead:
    """group_sync_read.py (Protocol 2.0 Sync Read; not the fast variant)."""

    def __init__(self, port, ph, start_address, data_length):
        self.port, self.ph = port, ph
        self.start_address, self.data_length = start_address, data_length
        self.last_result = False
        self.data_dict = {}

    def addParam(self, dxl_id):
        if dxl_id in self.data_dict:
            return False
        self.data_dict[dxl_id] = []
        return True

    def txRxPacket(self):
        if not self.data_dict:
            return COMM_NOT_AVAILABLE
        param = list(self.data_dict)
        result = self.ph.syncReadTx(self.port, self.start_address, self.data_length, param,
                                    len(param))
        if result != COMM_SUCCESS:
            return result
        self.last_result = False
        for dxl_id in self.data_dict:  # one readRx per ID, in the order they were added
            self.data_dict[dxl_id], result, _ = self.ph.readRx(self.port, dxl_id,
                                                               self.data_length)
            if result != COMM_SUCCESS:
                return result
        self.last_result = True
        return result

    def isAvailable(self, dxl_id, address, data_length):
        if not self.last_result or dxl_id not in self.data_dict:
            return False
        return self.start_address <= address <= self.start_address + self.data_length - data_length

    def getData(self, dxl_id, address, data_length):
        if not self.isAvailable(dxl_id, address, data_length):
            return 0
        data = self.data_dict[dxl_id][address - self.start_address:][:data_length]
        return sum(b << (8 * i) for i, b in enumerate(data))


# Protocol 1.0 packet offsets (protocol1_packet_handler.py)
P1_ID, P1_LENGTH, P1_INSTRUCTION, P1_ERROR, P1_PARAMETER0 = 2, 3, 4, 4, 5
P1_PACKET_MAX_LEN = 250


class Protocol1PacketHandler:
    """protocol1_packet_handler.py, for Ping, Read and Write."""

    def getProtocolVersion(self):
        return 1.0

    def txPacket(self, port, txpacket):
        total = txpacket[P1_LENGTH] + 4
        if port.is_using:
            return COMM_PORT_BUSY
        port.is_using = True
        if total > P1_PACKET_MAX_LEN:
            port.is_using = False
            return COMM_TX_ERROR
        txpacket[0:2] = [0xFF, 0xFF]
        txpacket[total - 1] = ~sum(txpacket[2:total - 1]) & 0xFF
        port.clearPort()
        if port.writePort(txpacket) != total:
            port.is_using = False
            return COMM_TX_FAIL
        return COMM_SUCCESS

    def rxPacket(self, port):
        rxpacket = []
        result = COMM_TX_FAIL
        wait_length = 6  # FF FF ID LENGTH ERROR CHECKSUM
        while True:
            rxpacket.extend(port.readPort(wait_length - len(rxpacket)))
            rx_length = len(rxpacket)
            if rx_length >= wait_length:
                idx = 0
                for idx in range(0, rx_length - 1):
                    if rxpacket[idx] == 0xFF and rxpacket[idx + 1] == 0xFF:
                        break
                if idx == 0:
                    if (rxpacket[P1_ID] > 0xFD or rxpacket[P1_LENGTH] > P1_PACKET_MAX_LEN or
                            rxpacket[P1_ERROR] > 0x7F):
                        del rxpacket[0]
                        continue
                    if wait_length != rxpacket[P1_LENGTH] + P1_LENGTH + 1:
                        wait_length = rxpacket[P1_LENGTH] + P1_LENGTH + 1
                        continue
                    if rx_length < wait_length:
                        if port.isPacketTimeout():
                            result = COMM_RX_CORRUPT
                            break
                        continue
                    checksum = ~sum(rxpacket[2:wait_length - 1]) & 0xFF
                    result = COMM_SUCCESS if rxpacket[wait_length - 1] == checksum \
                        else COMM_RX_CORRUPT
                    break
                del rxpacket[0:idx]
            elif port.isPacketTimeout():
                result = COMM_RX_TIMEOUT if rx_length == 0 else COMM_RX_CORRUPT
                break
        port.is_using = False
        return rxpacket, result

    def txRxPacket(self, port, txpacket):
        result = self.txPacket(port, txpacket)
        if result != COMM_SUCCESS:
            return None, result, 0
        if txpacket[P1_INSTRUCTION] == INST_BULK_READ:
            result = COMM_NOT_AVAILABLE
        if txpacket[P1_ID] == BROADCAST_ID or txpacket[P1_INSTRUCTION] == INST_ACTION:
            port.is_using = False
            return None, result, 0
        if txpacket[P1_INSTRUCTION] == INST_READ:
            port.setPacketTimeout(txpacket[P1_PARAMETER0 + 1] + 6)
        else:
            port.setPacketTimeout(6)
        while True:
            rxpacket, result = self.rxPacket(port)
            if result != COMM_SUCCESS or txpacket[P1_ID] == rxpacket[P1_ID]:
                break
        error = rxpacket[P1_ERROR] if result == COMM_SUCCESS else 0
        return rxpacket, result, error

    @staticmethod
    def instruction(dxl_id, inst, params=()):
        return [0, 0, dxl_id, len(params) + 2, inst, *params, 0]

    def ping(self, port, dxl_id):
        if dxl_id >= BROADCAST_ID:
            return 0, COMM_NOT_AVAILABLE, 0
        _, result, error = self.txRxPacket(port, self.instruction(dxl_id, INST_PING))
        model = 0
        if result == COMM_SUCCESS:  # the SDK then reads Model Number (address 0, 2 bytes)
            data, result, error = self.readTxRx(port, dxl_id, 0, 2)
            if result == COMM_SUCCESS:
                model = DXL_MAKEWORD(data[0], data[1])
        return model, result, error

    def broadcastPing(self, port):
        return None, COMM_NOT_AVAILABLE

    def readTxRx(self, port, dxl_id, address, length):
        if dxl_id >= BROADCAST_ID:
            return [], COMM_NOT_AVAILABLE, 0
        rxpacket, result, error = self.txRxPacket(
            port, self.instruction(dxl_id, INST_READ, [address, length]))
        if result != COMM_SUCCESS:
            return [], result, error
        return rxpacket[P1_PARAMETER0:P1_PARAMETER0 + length], result, rxpacket[P1_ERROR]

    def read1ByteTxRx(self, port, dxl_id, address):
        data, result, error = self.readTxRx(port, dxl_id, address, 1)
        return (data[0] if result == COMM_SUCCESS else 0), result, error

    def read2ByteTxRx(self, port, dxl_id, address):
        data, result, error = self.readTxRx(port, dxl_id, address, 2)
        return (DXL_MAKEWORD(*data) if result == COMM_SUCCESS else 0), result, error

    def writeTxRx(self, port, dxl_id, address, length, data):
        _, result, error = self.txRxPacket(
            port, self.instruction(dxl_id, INST_WRITE, [address, *data[:length]]))
        return result, error

    def write1ByteTxRx(self, port, dxl_id, address, data):
        return self.writeTxRx(port, dxl_id, address, 1, [data])

    def write2ByteTxRx(self, port, dxl_id, address, data):
        return self.writeTxRx(port, dxl_id, address, 2, le_bytes(data, 2))
