#!/usr/bin/env python3
"""Writes the hand-written seeds of fuzz_bus_feetech into tests/fuzz/corpus/bus_feetech/.

Each seed is a FEETECH bus session in the fuzz input layout of fuzz_input.hpp: byte 0 holds the
number of leading chunks and, in bits 5-7, the client's rate (fuzz_bus.cpp's kFeetechClientBps:
0 is 1 Mbit/s, 1 is 500000); one chunk per packet (the first 15), each 6 ms after the one before
so that the replies to a packet are out before the next comes. The IDs are those of fuzz_bus.cpp's
kFeetechServos. The other files of the directory (named by their SHA-1) are what long runs found;
this script leaves them alone. Run from the repository root: python3 tests/fuzz/feetech_bus_seeds.py
"""
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "bus_feetech")
GAP = 130  # gap units (fuzz_bus.cpp gap_duration): 6 ms
LONG = 255  # the longest gap, 2 s: past a Restart's boot (1800 ms)
PING, READ, WRITE, REG, ACTION, RECOVERY, RESTART, BACKUP, RESET, CALIB, SREAD, SWRITE = (
    0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x08, 0x09, 0x0A, 0x0B, 0x82, 0x83)
BC = 0xFE


def pkt(packet_id, instruction, *params):
    """One FT-SCS instruction packet: FF FF ID LENGTH INSTRUCTION PARAMS ~SUM."""
    body = [packet_id, len(params) + 2, instruction, *params]
    return [0xFF, 0xFF, *body, (~sum(body)) & 0xFF]


def seed(name, packets, rate=0, gaps=None):
    gaps = gaps or {}
    chunks = [(len(p), gaps.get(k, GAP)) for k, p in enumerate(packets[:15])]
    out = [len(chunks) | (rate << 5)]
    for length, gap in chunks:
        out += [length, gap]
    out += [b for p in packets for b in p]
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(bytes(out))


def main():
    os.makedirs(OUT, exist_ok=True)
    seed('response_level_0', [pkt(1,WRITE,8,0), pkt(1,PING), pkt(1,READ,56,2), pkt(1,WRITE,42,0,8),
         pkt(1,REG,42,0,4), pkt(1,ACTION), pkt(1,0x30), pkt(BC,SREAD,56,2,1,2,3), pkt(1,WRITE,8,1), pkt(1,PING)])
    seed('restart_then_ping', [pkt(1,RESTART), pkt(1,PING), pkt(1,PING), pkt(3,RESTART), pkt(3,PING)], gaps={2:LONG, 4:LONG})
    seed('broadcast_ping_collides', [pkt(BC,PING), pkt(3,PING), pkt(5,PING), pkt(2,PING)])
    seed('sync_read_chain', [pkt(BC,SREAD,56,2,1,3,4,5,2,9,6), pkt(BC,SREAD,3,2,1,1,3), pkt(BC,SREAD,0,70,4,5), pkt(BC,SREAD,56,2,5,4,3,2,1), pkt(BC,SREAD,56,2,1,9,3)])
    bad=pkt(1,READ,56,2); bad[-1]^=0xFF
    bad2=pkt(2,WRITE,42,0,8); bad2[-1]^=0x55
    bad3=pkt(BC,PING); bad3[-1]^=1
    bad4=pkt(3,PING); bad4[-1]^=2
    seed('bad_checksums', [bad, bad2, bad3, bad4, pkt(1,PING)])
    seed('scs0009_big_endian', [pkt(3,WRITE,40,1), pkt(3,WRITE,42,0x01,0x00), pkt(3,READ,42,2), pkt(3,READ,56,2),
         pkt(3,CALIB), pkt(3,RESET), pkt(3,READ,3,2)], gaps={3:LONG})
    seed('unicast_group_and_unknown', [pkt(1,SREAD,56,2,1,2), pkt(1,SWRITE,42,2,1,0,8), pkt(1,0x92,0,0), pkt(4,0x8A,56,2),
         pkt(5,0x10), pkt(BC,0x20), pkt(1,READ,56), pkt(1,ACTION)])
    seed('lock_id_backup_recovery', [pkt(4,WRITE,55,0), pkt(4,BACKUP), pkt(4,WRITE,5,9), pkt(9,PING), pkt(9,WRITE,55,1),
         pkt(9,RECOVERY), pkt(9,WRITE,55,0), pkt(9,RECOVERY), pkt(4,PING), pkt(9,PING)])
    seed('hls_sms_motion', [pkt(5,WRITE,40,1), pkt(4,WRITE,40,1), pkt(BC,SWRITE,42,2,4,0,12,5,0,4), pkt(BC,SREAD,56,2,4,5),
         pkt(BC,SREAD,56,2,4,5)], gaps={3:LONG, 4:LONG})
    seed('sts_calibrate_wheel', [pkt(1,WRITE,40,128), pkt(1,READ,56,2), pkt(1,CALIB,0,4), pkt(1,READ,31,2),
         pkt(1,WRITE,33,1), pkt(1,WRITE,46,0xE8,0x83), pkt(1,WRITE,40,1), pkt(1,READ,58,2)], gaps={7:LONG})
    seed('baud_500000', [pkt(6,PING), pkt(6,READ,56,2), pkt(BC,PING), pkt(1,PING)], rate=1)
    seed('baud_change', [pkt(1,WRITE,6,1), pkt(1,PING)], rate=0)
    seed('broadcast_id_write_collides', [pkt(BC,WRITE,5,1), pkt(1,PING), pkt(1,READ,56,2), pkt(BC,SREAD,56,2,1), pkt(1,WRITE,42,0,8)])
    # docs/feetech.md "Refusals": silence to a bad checksum, an unknown or malformed instruction
    # and a read past the table (SCS0009's ends at 83, the others' at 86), in a SYNC READ too
    # (ID 3 stops the chain); an acknowledgement to a write of read-only 85 and a READ of 0 bytes.
    bad5=pkt(1,PING); bad5[-1]^=4
    seed('refusals_silent_or_acknowledged', [bad5, pkt(1,0x30,1), pkt(1,READ,56), pkt(1,READ,86,2), pkt(3,READ,84,1),
         pkt(1,READ,0,0), pkt(1,WRITE,85,254), pkt(BC,SREAD,84,2,1,3,4), pkt(BC,SREAD,86,2,4,5), pkt(1,ACTION),
         pkt(3,CALIB), pkt(1,PING)])
    seed('calibration_out_of_reach', [pkt(5,CALIB,0x07,0xFF), pkt(5,READ,31,2), pkt(1,CALIB,0,0), pkt(1,READ,31,2),
         pkt(4,CALIB,0xFF,0xFF), pkt(4,WRITE,40,128), pkt(4,READ,56,2)])


if __name__ == "__main__":
    main()
