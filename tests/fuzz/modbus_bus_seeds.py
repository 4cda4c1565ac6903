#!/usr/bin/env python3
"""Writes the hand-written seeds of fuzz_bus_modbus into tests/fuzz/corpus/bus_modbus/.

Each seed is a session on fuzz_bus_modbus.cpp's bus (PH54-200-S500-R at 1, PM42-010-S260-R at 2,
RH-P12-RN(A) at 247 and at 2, all speaking Modbus RTU) in the fuzz input layout of fuzz_input.hpp:
byte 0 holds the number of leading chunks and, in bits 5-7, the line (fuzz_bus_modbus.cpp's
kLines: 0 is 57600 bit/s with modelled delays, 1 the same without, 2 is 9600 bit/s); one chunk
per frame (the first 15), each 66 ms after the one before has left the line, so that its
response is out before the next frame comes. Register R holds control-table bytes 2R (low) and
2R + 1 (high). The other files of the directory (named by their SHA-1) are what long runs
found, and regression-* the inputs of what they found; this script leaves both alone. Run from
the repository root:
python3 tests/fuzz/modbus_bus_seeds.py
"""
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "bus_modbus")
GAP = 160  # gap units (fuzz_bus_modbus.cpp gap_duration): 66 ms after the line is free
T15 = 30  # exactly the fixed t1.5 (750 us): the frame goes on
OVER_T15 = 31
T35 = 70  # exactly the fixed t3.5 (1,750 us): the frame ends
DEADLINE = 255  # 1 s

# Registers (control-table byte address / 2) of the DYNAMIXEL-P table.
ID_REG = 3  # Firmware Version (6, read-only), ID (7)
BAUD_REG = 4  # Baud Rate (8), Return Delay Time (9, N/A)
MODE_REG = 5  # Drive Mode (10), Operating Mode (11)
PROTOCOL_REG = 6  # Secondary ID (12, N/A), Protocol Type (13)
HOMING_REG = 10  # Homing Offset (20, 4 bytes)
INDIRECT_ADDRESS_REG = 84  # Indirect Address 1 (168, N/A)
TORQUE_REG = 256  # Torque Enable (512), LED Red (513)
SRL_REG = 258  # Status Return Level (516), Registered Instruction (517): both N/A
GOAL_CURRENT_REG = 275  # Goal Current (550)
GOAL_VELOCITY_REG = 276  # Goal Velocity (552, 4 bytes)
ACCEL_REG = 278  # Profile Acceleration (556, 4 bytes)
GOAL_POSITION_REG = 282  # Goal Position (564, 4 bytes)
PRESENT_POSITION_REG = 290  # Present Position (580, 4 bytes)
INDIRECT_DATA_REG = 317  # Indirect Data 1 (634)


def crc_modbus(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def frame(address, function, *data):
    body = [address, function, *data]
    crc = crc_modbus(body)
    return body + [crc & 0xFF, crc >> 8]


def be16(v):
    return [(v >> 8) & 0xFF, v & 0xFF]


def read(address, reg, count, function=0x03):
    return frame(address, function, *be16(reg), *be16(count))


def write1(address, reg, value):
    return frame(address, 0x06, *be16(reg), *be16(value))


def write(address, reg, *values):
    data = [b for v in values for b in be16(v)]
    return frame(address, 0x10, *be16(reg), *be16(len(values)), len(data), *data)


def write_read(address, read_reg, read_count, write_reg, *values):
    data = [b for v in values for b in be16(v)]
    return frame(address, 0x17, *be16(read_reg), *be16(read_count), *be16(write_reg),
                 *be16(len(values)), len(data), *data)


def crc_dxl(data):
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def v2(packet_id, instruction, *params):
    """A Protocol 2.0 instruction packet (no parameter here needs stuffing)."""
    body = [0xFF, 0xFF, 0xFD, 0x00, packet_id, *le16(len(params) + 3), instruction, *params]
    return body + le16(crc_dxl(body))


def le16(v):
    return [v & 0xFF, (v >> 8) & 0xFF]


def broken(f):
    return f[:-1] + [f[-1] ^ 0xFF]


def seed(name, frames, line=0, gaps=None):
    """One chunk per frame; gaps: {frame index: gap before it} (default GAP)."""
    gaps = gaps or {}
    chunks = [(len(f), gaps.get(k, GAP if k else 0)) for k, f in enumerate(frames[:15])]
    out = [len(chunks) | (line << 5)]
    for length, gap in chunks:
        out += [length, gap]
    out += [b for f in frames for b in f]
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(bytes(out))


def main():
    os.makedirs(OUT, exist_ok=True)
    # Model Number at 40001 from each address; 2 collides (PM42 and RH-P12-RN(A)).
    seed('model_numbers', [read(1, 0, 2), read(247, 0, 2), read(2, 0, 2), read(3, 0, 2)])
    seed('torque_goal_present', [write1(1, MODE_REG, 0x0300), write1(1, TORQUE_REG, 1),
         write(1, GOAL_POSITION_REG, 0x4E20, 0), read(1, PRESENT_POSITION_REG, 2),
         read(1, PRESENT_POSITION_REG, 2)], gaps={4: DEADLINE})
    seed('exceptions', [write1(1, 0, 5), write(1, PRESENT_POSITION_REG, 0, 0),
         write1(1, GOAL_POSITION_REG, 0x10), write1(1, MODE_REG, 0x0200),
         frame(1, 0x01, 0, 0, 0, 1), read(1, 0, 0), read(1, 0, 126), read(1, 0x7F00, 1),
         read(1, 0x7FFF, 2)])
    seed('eeprom_locked', [write1(247, TORQUE_REG, 1), write1(247, MODE_REG, 0x0400),
         write1(247, BAUD_REG, 0x0003), write1(247, TORQUE_REG, 0), write1(247, MODE_REG, 0x0500)])
    seed('absent_items', [read(1, SRL_REG, 1), write1(1, SRL_REG, 0), read(1, INDIRECT_ADDRESS_REG, 1),
         read(1, BAUD_REG, 1), write1(1, BAUD_REG, 0x0701), read(1, PROTOCOL_REG, 1),
         read(1, BAUD_REG, 4), write(1, INDIRECT_ADDRESS_REG, 0x0100, 0x0200),
         read(1, INDIRECT_DATA_REG, 2)])
    seed('id_change', [write1(1, ID_REG, 0x0500), read(5, 0, 2), read(1, 0, 2), write1(5, ID_REG, 0),
         write1(5, ID_REG, 0xF800), write1(5, ID_REG, 0xF700), read(247, 0, 2),
         write1(247, ID_REG, 0x0100), read(1, 0, 1)])
    seed('baud_change', [write1(1, BAUD_REG, 0x0000), read(1, 0, 2), read(2, 0, 1),
         write1(247, BAUD_REG, 0x0003), read(247, 0, 1)])
    seed('protocol_2_and_back', [write1(247, PROTOCOL_REG, 0x0200), read(247, 0, 1),
         v2(247, 0x01), v2(247, 0x02, *le16(0), *le16(4)), v2(247, 0x03, *le16(13), 10),
         read(247, 0, 2), v2(247, 0x01)])
    seed('broadcast', [write1(0, TORQUE_REG, 1), read(0, 0, 2), write(0, GOAL_POSITION_REG, 0, 0),
         frame(0, 0x08, 0, 0, 1, 2), read(1, TORQUE_REG, 1)])
    seed('diagnostics', [frame(1, 0x08, 0, 0, 0x12, 0x34), frame(247, 0x08, 0, 0),
         frame(1, 0x08, 0, 1, 0, 0), frame(2, 0x08, 0, 0, 0xAB), frame(1, 0x08, 0)])
    seed('read_write_multiple', [write_read(1, 0, 2, TORQUE_REG, 1),
         write_read(1, GOAL_POSITION_REG, 2, GOAL_POSITION_REG, 0x1000, 0),
         write_read(247, PRESENT_POSITION_REG, 4, TORQUE_REG, 0), write_read(1, 0, 125, TORQUE_REG, 0),
         write_read(2, 0, 1, SRL_REG, 0)])
    seed('read_input_registers', [read(1, 0, 2, 0x04), read(247, GOAL_POSITION_REG, 2, 0x04),
         read(2, 0, 125, 0x04), read(1, 0x7FFF, 1, 0x04)])
    seed('bad_crcs', [broken(read(1, 0, 2)), broken(write1(1, TORQUE_REG, 1)), read(1, TORQUE_REG, 1),
         broken(frame(247, 0x08, 0, 0, 1))])
    seed('split_at_t15', [read(1, 0, 2)[:3], read(1, 0, 2)[3:], read(1, 0, 2)[:5], read(1, 0, 2)[5:],
         read(247, 0, 1)], gaps={1: T15, 3: OVER_T15})
    seed('back_to_back', [read(1, 0, 2) + read(247, 0, 2), read(1, 0, 2), read(247, 0, 2),
         write1(1, TORQUE_REG, 1)], gaps={2: T35, 3: T15})
    seed('at_9600', [read(1, 0, 2), write1(1, TORQUE_REG, 1), read(247, 0, 1)], line=2)
    seed('without_delays', [read(1, 0, 2), read(247, 0, 2), write1(1, TORQUE_REG, 1),
         read(1, TORQUE_REG, 1), read(2, 0, 1)], line=1, gaps={1: 0, 2: 0, 3: 1, 4: 0})
    seed('without_delays_1m', [read(1, 0, 2), write1(1, BAUD_REG, 0x0001), read(1, 0, 2)], line=7)
    seed('write_many', [write(1, 0, *range(123)), write(1, TORQUE_REG, *([0] * 40)),
         write(247, GOAL_CURRENT_REG, 100), write(247, GOAL_VELOCITY_REG, 100, 0),
         write(1, ACCEL_REG, 10, 0, 20, 0), write(1, HOMING_REG, 0xFFFF, 0xFFFF)])
    seed('read_many', [read(1, 0, 125), read(1, 125, 125), read(1, 250, 125), read(1, 375, 125),
         read(247, 300, 125), read(2, 0, 125)])
    seed('goal_out_of_range', [write(1, GOAL_POSITION_REG, 0xFFFF, 0x7FFF), write1(1, TORQUE_REG, 1),
         write(1, GOAL_POSITION_REG, 0, 0x8000), write(247, GOAL_POSITION_REG, 0x2000, 0),
         write(1, GOAL_VELOCITY_REG, 0xFFFF, 0x7FFF)])
    seed('gripper_at_247', [write1(247, TORQUE_REG, 1), write(247, GOAL_POSITION_REG, 740, 0),
         read(247, PRESENT_POSITION_REG, 2), read(247, GOAL_CURRENT_REG, 1)], gaps={3: DEADLINE})
    seed('shared_address_writes', [write1(2, TORQUE_REG, 1), write(2, GOAL_POSITION_REG, 500, 0),
         read(2, TORQUE_REG, 1), write1(2, ID_REG, 0x0300), read(3, 0, 2), read(2, 0, 2)])
    seed('unknown_functions', [frame(1, 0x01, 0, 0, 0, 8), frame(1, 0x05, 0, 0, 0xFF, 0),
         frame(1, 0x2B, 0x0E, 1, 0), frame(1, 0x83, 0, 0, 0, 1), frame(247, 0x7F),
         frame(1, 0x16, 0, 1, 0xFF, 0, 0, 1)])
    seed('malformed', [frame(1, 0x03, 0, 0, 0), frame(1, 0x06, 0, 0), frame(1, 0x10, 0, 0, 0, 2, 2, 0, 0),
         frame(1, 0x10, 0, 0, 0, 0, 0), frame(1, 0x17, 0, 0, 0, 1, 0, 0, 0, 0, 0),
         frame(1, 0x10, 0, 0, 0, 1, 2, 0), frame(1, 0x08)])
    seed('deadline_gaps', [read(1, 0, 2)[:4], read(1, 0, 2)[4:], read(1, 0, 2), write1(1, TORQUE_REG, 1)],
         gaps={1: DEADLINE, 2: DEADLINE, 3: DEADLINE})
    seed('protocol_2_broadcast_ping', [write1(1, PROTOCOL_REG, 0x0200), v2(0xFE, 0x01),
         v2(1, 0x03, *le16(13), 10), read(1, 0, 2), v2(1, 0x01)])
    seed('id_0_over_2_then_modbus', [write1(1, PROTOCOL_REG, 0x0200), v2(1, 0x03, *le16(7), 0),
         v2(0, 0x03, *le16(13), 10), read(0, 0, 2), write1(0, TORQUE_REG, 1), read(1, 0, 2)])
    seed('led_and_torque', [write1(1, TORQUE_REG, 0x0101), read(1, TORQUE_REG, 2),
         write(1, TORQUE_REG, 0x0101, 0x0101), read(1, TORQUE_REG, 2)])


if __name__ == "__main__":
    main()
