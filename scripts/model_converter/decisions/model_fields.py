"""Model-level decisions, as data: the fields of a model that the pages do not state (firmware
version, reply timing, boot time, protocols, degrees per pulse), baud tables that were not
copied, the Indirect blocks the pages must show, and the dual-axis modules. Each entry carries the
note written into the model with it. Tables keyed by variant fall back to the family where the
variant has no entry of its own (catalogue.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from . import EMANUAL_INCLUDES

# Firmware Version: the pages print "-". Lowest version that has every instruction and item the
# page shows, per ../protocol2.md, ../protocol1.md and the includes; the builder refuses a version
# below any "available from firmware vNN" of the page's description sections (firmware.py).
# Entries under a page name are pages whose notes ask more than their family's version.
# The DYNAMIXEL-P pages with Startup Configuration(60): their own row, or (PH42, PM54-040/060) the
# row borrowed from a newer P page (item_rules.BORROWED_ROWS), whose note then applies too.
_P_STARTUP_FIRMWARE = (45, "firmware_version: the page shows '-'; 45: the Startup Configuration(60) note "
                           "'Startup Configuration is available from firmware V45' (the include's branch for every "
                           "product group but XL330/XC330; the row is this page's, or borrowed from a newer P page), "
                           "above 12 for Fast Sync Read / Fast Bulk Read (protocol2.md: 'P Series(Fw v12 or above)') "
                           "and Backup Ready ('available from firmware V12')")

FIRMWARE = {
    "x": (45, "firmware_version: the page shows '-'; 45 is the lowest X430/540 firmware with every "
              "feature the table and protocol2.md describe: Fast Sync Read / Fast Bulk Read (X430/540 "
              "fw v45+), Startup Configuration(60) ('available from firmware V45'), the broadcast "
              "Factory Reset 0xFF guard (fw 42+), time-based profiles (fw 42+), Bus Watchdog (v38+)"),
    "x330": (53, "firmware_version: the page shows '-'; 53, what a buyer gets today: the page's note 'Firmware "
                 "versions prior to V53 support up to 20 Indirect Address/Data items. The address range for "
                 "Indirect Address is 168 ~ 207, and for Indirect Data is 208 ~ 227.' makes the 28-item Indirect "
                 "blocks it prints a V53-or-later table (the older one is firmware_variants' 52). 53 also covers "
                 "Fast Sync Read / Fast Bulk Read (protocol2.md: X330 fw v46+) and the page's 'available from "
                 "firmware V46' items (Torque On by Goal Update, Startup Configuration, Backup Ready)"),
    "xm335-t323": (46, "firmware_version: the page shows '-'; 46 is the lowest X330 firmware with Fast Sync Read / "
                       "Fast Bulk Read (protocol2.md: X330 fw v46+), above the page's 'Startup Configuration is "
                       "available from firmware V45' and 'Backup Ready is available from firmware V45'. The page has "
                       "no 'prior to V53' Indirect note (its Indirect blocks have no older layout), so the XL330/XC330 "
                       "V53 floor does not apply and it has no firmware variant"),
    "mx2": (42, "firmware_version: the page shows '-'; 42 covers the broadcast Factory Reset 0xFF guard "
                "(protocol2.md: 'MX(2.0) FW42') and time-based profiles (fw 42); Fast Sync/Bulk Read "
                "are not supported on MX(2.0) at any version"),
    "mx1": (40, "firmware_version: the page shows '-'; 40 is the first MX Protocol 1.0 firmware with "
                "the Reboot instruction (protocol1.md: 'MX-28/64/106(V40)') and Realtime Tick(50) "
                "('available from Firmware v40')"),
    "mx-12w": (41, "firmware_version: the page shows '-'; 41: the page's Realtime-Tick(50) note 'This feature is "
                   "available from Firmware v41' (the MX-28/64/106 pages say v40), which also covers the Reboot "
                   "instruction (protocol1.md: 'MX-28/64/106(V40)')"),
    "p": (12, "firmware_version: the page shows '-'; 12 is the lowest P-series firmware with Fast Sync "
              "Read / Fast Bulk Read (protocol2.md: 'P Series(Fw v12 or above)')"),
    **{name: _P_STARTUP_FIRMWARE for name in ("ph54-100-s500-r", "ph54-200-s500-r", "pm42-010-s260-r",
                                               "ph42-020-s300-r", "pm54-040-s250-r", "pm54-060-s250-r")},
    "pro": (1, "firmware_version: the page shows '-'; no instruction or item of the legacy PRO table "
               "depends on a firmware version in the reference, so 1 is an arbitrary placeholder"),
    "xl320": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the XL-320 "
                 "firmware version, so 1 is an arbitrary placeholder"),
    "ax": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the AX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "rx": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the RX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "ex": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the EX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "rh-p12-rna": (13, "firmware_version: the page shows '-'; 13 is the lowest RH-P12-RN(A) firmware with Fast Sync "
                       "Read / Fast Bulk Read (protocol2.md: 'RH-P12-RN(A) (Fw v13 or above)')"),
    "rh-p12-rn": (1, "firmware_version: the page shows '-'; no instruction or item of the RH-P12-RN (PRO-style) "
                     "table depends on a firmware version in the reference, so 1 is an arbitrary placeholder"),
    "dx": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the DX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "pro_a": (1, "firmware_version: the page shows '-'; no instruction or item of the PRO(A) table depends on a "
                 "firmware version in the reference (protocol2.md lists no PRO(A) among the Fast Sync/Bulk Read "
                 "servos), so 1 is an arbitrary placeholder"),
    "y": (1, "firmware_version: the page shows '-' (its Firmware Version block says only 'The firmware version "
             f"installed on your DYNAMIXEL', {EMANUAL_INCLUDES}y/control_table_6_firmware_version.md); no "
             "instruction or item of the DYNAMIXEL-Y table depends on a firmware version in the reference "
             "(protocol2.md lists no Y servo among the Fast Sync/Bulk Read or Control Table Backup servos), so 1 is "
             "an arbitrary placeholder"),
}

# The firmware that stands for "Firmware versions prior to VNN" (firmware.py's older_indirect): the
# last version before NN, as DynamixelSDK names that layout (xl330_m288_fw52.model for V53).
OLDER_FIRMWARE_NOTE = ("firmware_variants: {version}, the page's note '{quote}' ({version} = the last version "
                       "before V{before}, as DynamixelSDK's *_fw{version}.model files name that table): Indirect "
                       "Address 1 ~ {count} at {address} ~ {address_end}, Data at {data} ~ {data_end}; every other "
                       "item is the same")

# Reply timing per family: the figures and the note. Only the AX-12 is measured.
_TIMING_AX = ({"ping_us": 18, "read_us": 22, "write_us": 24, "write_per_byte_us": 6},
              "timing: ping 18 us, read 22 us, write 24 us + 6 us per data byte, as measured on an AX-12 "
              "(figures given with the converter's brief); used for RX and EX as the same Protocol 1.0 "
              "generation")
_TIMING_OTHER = ({"ping_us": 50, "read_us": 50, "write_us": 50, "write_per_byte_us": 0},
                 "timing: 50 us for ping, read and write, none per byte ('MX about 50 us'); the same figure "
                 "is used for X, XL-320, P and PRO, for which nothing is measured")
TIMING = {"ax": _TIMING_AX, "rx": _TIMING_AX, "ex": _TIMING_AX, "mx1": _TIMING_OTHER, "mx2": _TIMING_OTHER,
          "x": _TIMING_OTHER, "xl320": _TIMING_OTHER, "p": _TIMING_OTHER, "pro": _TIMING_OTHER,
          "y": (_TIMING_OTHER[0], "timing: 50 us for ping, read and write, none per byte, the figure used for the other "
                                  "Protocol 2.0 families ('MX about 50 us'); nothing is measured for DYNAMIXEL-Y")}

BOOT_MS = 400
BOOT_URL = "https://github.com/ROBOTIS-GIT/emanual/issues/1698"
BOOT_NOTE = (f"timing.boot_ms: {BOOT_MS} ms. The e-Manual gives no figure; the only stated one found is "
             f"ROBOTIS-GIT/emanual issue #1698 ({BOOT_URL}): XC330 servos answer the Reboot instruction "
             "at once, then 'refuse to reply for about 0.4 seconds while rebooting' (the maintainers "
             "declined to document it). No per-model figure exists, so 400 ms is used for every model "
             "(Dynamixel2Arduino waits up to 3 s, an upper bound rather than a measurement)")

RETURN_DELAY_UNIT_US = 2
RETURN_DELAY_NOTE = "return_delay_unit_us: 2 (Return Delay Time include: 'its unit is 2 [usec]')"

DEFAULT_ID = 1

# Pages that print another model's number: the servo reports it (the page is the reference), and
# the model file names the other model so the library accepts the shared number.
SHARED_MODEL_NUMBERS = {
    "xc430-t150bb": ("xc430-w150", "shares_model_number_with: the page prints 1,070, XC430-W150's number (the "
                                   "BB version 'applies metal ball bearings ... instead of plastic bushing'; "
                                   "DynamixelSDK's dynamixel.model has no BB entry, 1070 = xc430_w150.model). "
                                   "Kept: a client reads 1070 and treats it as an XC430-W150, whose table is the "
                                   "same, row for row"),
    "xc430-t240bb": ("xc430-w240", "shares_model_number_with: the page prints 1,080, XC430-W240's number (the "
                                   "ball-bearing version; dynamixel.model has no BB entry, 1080 = "
                                   "xc430_w240.model). Kept, as for XC430-T150BB"),
    "xw430-t200": ("xw430-t333", "shares_model_number_with: the page prints 1,270, XW430-T333's number, and "
                                 "DynamixelSDK registers no number for its xw430_t200.model (XW430-T333's table "
                                 "has the same items at the same addresses; factory values differ, e.g. Velocity "
                                 "Limit 235 here, 139 there). Kept as printed: no other number is stated anywhere "
                                 "in the reference"),
}

# Protocols per variant, and the note where the list needs one.
# DYNAMIXEL-P and RH-P12-RN(A) speak Modbus RTU through Protocol Type(13) = 10
# (modbus/modbus-rtu.md "Where DYNAMIXEL speaks it"); their map is read by modbus_map.py.
_MODBUS_NOTE = ("protocols: DYNAMIXEL Protocol 2.0 by default, Modbus RTU through Protocol Type(13) = 10 (from the "
                "firmware the modbus note names); the Modbus register map is the page's Modbus "
                "Address column, checked row by row against holding register 40001 + floor(address / 2) (an even "
                "address the register's low byte, an odd one its high byte); the items it prints 'N/A' are "
                "absent_in modbus (docs/modbus.md)")
_PROTOCOLS_1 = ([1], None)
_PROTOCOLS_2_AND_1 = ([2, 1], "protocols: 2.0 by default, 1.0 through Protocol Type(13) = 1")
PROTOCOLS = {
    "ax": _PROTOCOLS_1, "rx": _PROTOCOLS_1, "ex": _PROTOCOLS_1, "mx1": _PROTOCOLS_1,
    "x": _PROTOCOLS_2_AND_1, "mx2": _PROTOCOLS_2_AND_1,
    "x330": ([2], "protocols: 2.0 only; Protocol Type 20/21/22 select RC receiver protocols (S.BUS, iBUS, "
                  "RC-PWM), which are not DYNAMIXEL bus protocols"),
    "p": ([2, "modbus"], _MODBUS_NOTE),
    # PRO(A) falls back to P elsewhere, but its pages have no Protocol Type item and no Modbus column.
    "pro_a": ([2], "protocols: 2.0 only; the page has no Protocol Type item and no Modbus Address column"),
    "pro": ([2], None),
    "xl320": ([2], None),
    "y": ([2], "protocols: 2.0 only; the page's Protocol Type(11) row prints '2 (Dynamixel Protocol 2.0)' and "
               "'10 (Modbus)' and its table has a Modbus Address column, but dxlemu does not offer Modbus RTU on "
               "DYNAMIXEL-Y because the sources disagree: another revision of the Y Protocol Type include marks "
               "10 'TBD' and says Modbus will come later (modbus/modbus-rtu.md 'Where DYNAMIXEL speaks it'; "
               "docs/modbus.md). The item accepts both values; the Modbus Address column and the Modbus-only "
               "rows are not read"),
}

# Baud tables that are not in the offline reference (P and PRO includes were not copied).
EXTERNAL_BAUD = {
    "p": ([(0, 9600), (1, 57600), (2, 115200), (3, 1000000), (4, 2000000), (5, 3000000),
           (6, 4000000), (7, 4500000), (8, 6000000), (9, 10500000)],
          EMANUAL_INCLUDES + "p/control_table_8_baud_rate.md"),
    "pro": ([(0, 9600), (1, 57600), (2, 115200), (3, 1000000), (4, 2000000), (5, 3000000),
             (6, 4000000), (7, 4500000), (8, 10500000)],
            EMANUAL_INCLUDES + "control_table_8_baudrate_pro.md"),
    # Its Value table: 0 9,600 / 1 57,600 (Default) / 2 115,200 / 3 1M / 4 2M / 5 3M / 6 4M / 7 4.5M /
    # 8 6M / 9 10.5M (nominal rates).
    "y": ([(0, 9600), (1, 57600), (2, 115200), (3, 1000000), (4, 2000000), (5, 3000000),
           (6, 4000000), (7, 4500000), (8, 6000000), (9, 10500000)],
          EMANUAL_INCLUDES + "y/control_table_12_baud_rate.md"),
}

# Families whose Baud Rate value n means 2,000,000/(n+1) bps, beyond the values their table lists.
BAUD_FORMULA_FAMILIES = {"ax", "rx", "ex", "mx1"}
BAUD_FORMULA_NOTE = ("baud_rates: Baud Rate value n means 2,000,000/(n+1) bps for every n in 0 ~ 254 (MX 1.0: "
                     "250/251/252 are 2.25M/2.5M/3M); only the values the page's table lists are enumerated "
                     "(the format cannot state the formula); the item accepts 0 ~ 254")

# Degrees per encoder pulse per family, and the note.
_DPP_4096 = (360 / 4096, "motion.degrees_per_pulse: 360/4096 (4,096 pulses per revolution, Unit column "
                         "'1 [pulse]' / models.tsv '4096 pulse/rev')")
_DPP_300_DEG = (300 / 1024, "motion.degrees_per_pulse: 300/1024 = 0.29296875 (the spec's 'Resolution 0.29 deg': "
                            "Goal Position 0 ~ 1,023 over 0 ~ 300 deg, 512 = 150 deg)")
_DPP_GRIPPER = (360 / 4096, "motion.degrees_per_pulse: 360/4096 (the RH-P12-RN specifications: 'Contactless "
                            "Absolute Encoder (12bit, 360 deg)', 'Degree of Precision 0.088 deg'; the stroke 0 (open) ~ "
                            "1,150 (closed) pulses is 0 ~ 109 mm, https://emanual.robotis.com/docs/en/platform/rh_p12_rn/)")
DEGREES_PER_PULSE = {
    "rh-p12-rn": _DPP_GRIPPER,
    "rh-p12-rna": _DPP_GRIPPER,
    "l42-10-s300-r": (360 / 4096, "motion.degrees_per_pulse: 360/4096 (the Goal Position description: 'position "
                                  "range 0 ~ 4,095'; Min/Max Position Limit default -2,047 / 2,048, one turn "
                                  "of 4,096 pulses), not the 180/250,961 of the larger PRO models"),
    "x": _DPP_4096, "mx2": _DPP_4096, "mx1": _DPP_4096,
    "ax": _DPP_300_DEG, "rx": _DPP_300_DEG, "xl320": _DPP_300_DEG,
    "ex": (251 / 4096, "motion.degrees_per_pulse: 251/4096 = 0.0613 (spec: 'Resolution 0.06 deg', 'Running "
                       "Degree 0 ~ 251 deg' over 4,096 positions); the page's Goal Position text still says "
                       "0.29 deg (inherited from RX pages, see README inconsistencies)"),
    "p": (float(Fraction(180, 501923)), "motion.degrees_per_pulse: 180/501,923 (Goal Position description: "
                                        "-180 ~ 180 deg = -501,923 ~ 501,923)"),
    "y": (360 / 524288, "motion.degrees_per_pulse: 360/524,288 (the Electronic Gear Ratio block: 'DYNAMIXEL-Y "
                        f"Resolution: 524,288 [pulse/rev]', {EMANUAL_INCLUDES}y/control_table_96_electronic_gear_ratio_"
                        "numerator.md; the factory Max/Min Position Limit +-262,144 are then +-180 deg). The Goal "
                        "Position block's '1[pulse] (Approx. 0.006866 deg)' is ten times 360/524,288 and agrees with "
                        "no resolution the pages state; the stated resolution is used"),
    "pro": (float(Fraction(180, 250961)), "motion.degrees_per_pulse: 180/250,961, derived from the default "
                                          "position limits +-250,961 taken as +-180 deg (models.tsv: 'derived "
                                          "from defaults, not stated')"),
}

# rev/min per velocity unit where models.tsv states none.
VELOCITY_UNITS = {
    "rh-p12-rn": (0.114, "motion.velocity_unit_rpm: 0.114 rev/min per unit (the Velocity Limit(32) description's "
                         "table: 'Unit 0.114 RPM'; models.tsv states none)"),
    "l42-10-s300-r": (0.114, "motion.velocity_unit_rpm: 0.114 rev/min per unit (Goal Velocity(600) description: "
                             "'the conversion unit is about 0.114rpm'; models.tsv states none)"),
}

# Expected Indirect Address / Data blocks: (first n, last n, first address, first data address).
INDIRECT_BLOCKS = {
    "x": [(1, 28, 168, 224), (29, 56, 578, 634)],   # README behaviour 22, X/MX(2.0) pages
    "x330": [(1, 28, 168, 224)],                      # XL330/XC330: only 1 ~ 28
    "mx2": [(1, 28, 168, 224), (29, 56, 578, 634)],
    "p": [(1, 128, 168, 634)],                       # PH54 page: 168 ~ 422, data 634 ~ 761
    "pro": [(1, 256, 49, 634)],                      # H54 page: 49 ~ 559, data 634 ~ 889
    "y": [(1, 128, 256, 634)],                       # YM pages: 256 ~ 510, data 634 ~ 761
}


@dataclass(frozen=True)
class DualAxis:
    """A module of two servos behind one control table (docs/control-table.md)."""
    shared_items: tuple      # items both axes share
    default_id_note: str
    note: str


DUAL_AXIS = {
    "2xl430-w250": DualAxis(
        ("baud_rate", "protocol_type"),
        "default_id: 1 for the first axis; the second axis of the module is ID 2 (ID(7) initial '1, 2')",
        "axes: two axes, each with this control table; Baud Rate(8) and Protocol Type(13) are shared "
        "('Attempting to change the Baud Rate of one joint will also affect the other joint'); EEPROM is "
        "writable only while both axes have Torque Enable 0 (README 16)"),
    "2xc430-w250": DualAxis(
        ("baud_rate", "protocol_type"),
        "default_id: 1 for the first axis; the second axis of the module is ID 2 (ID(7) initial '1, 2')",
        "axes: two axes, each with this control table; Baud Rate(8) and Protocol Type(13) are shared ('Only one "
        "Baud Rate can be used for the 2XC430-W250. Attempting to change the Baud Rate of one joint will also "
        "affect to the other joint', the same for Protocol Type); EEPROM is writable only while both axes have "
        "Torque Enable 0, as on the 2XL430-W250 (README 16)"),
}
